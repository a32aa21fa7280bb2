// The pressure-opened valves of the hydraulics plugin (relief-valve,
// check-valve; plugins/components/hydraulics/pressure_valve.hpp), driven through the C
// ABI by a fake host: their flow against the closed form of
// docs/hydraulics.md, no flow at or below the cracking pressure, the
// catalogue point met exactly, a continuous slope across every corner of the
// regularized opening (Newton needs it), dissipation >= 0, the analytic
// jacobian against central differences, and the option checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "plugins/fake_host.hpp"

namespace mh::test {
namespace {

// A relief valve set to 20 MPa, 2 MPa override, 100 l/min at 22 MPa.
constexpr double kCrack = 20e6, kOverride = 2e6, kQnom = 100.0 / 60000.0, kTank = 1e5;
constexpr double kSmooth = 0.1, kPtr = 2e5;

double orifice(double dp) {
  return dp / std::pow(dp * dp + kPtr * kPtr, 0.25);
}
double ramp(double u) {
  if (u <= 0) return 0;
  if (u < kSmooth) return u * u / (2 * kSmooth);
  return u - kSmooth / 2;
}
double opening(double u) {
  return ramp(u) - ramp(u - 1);
}

struct ValveFixture {
  FakeNetwork net;
  FakeHost host{net, "valve"};
  std::unique_ptr<Instance> valve;
  mh_status setup_status = MH_ERROR;
  int32_t in = -1, out = -1;
  std::string inlet, outlet;

  explicit ValveFixture(const std::string& id, double crack = kCrack, double extra_key_value = -1.0,
                        const std::string& extra_key = "")
      : inlet(id == "relief-valve" ? "P" : "A"), outlet(id == "relief-valve" ? "T" : "B") {
    host.numbers = {
        {"cracking_pressure", crack}, {"override_pressure", kOverride}, {"nominal_flow", kQnom}};
    if (!extra_key.empty()) host.numbers[extra_key] = extra_key_value;
    host.port_nodes = {{inlet, "n"}, {outlet, "tank"}};
    valve = std::make_unique<Instance>(id, host);
    setup_status = valve->setup();
    if (setup_status == MH_OK) {
      in = host.port(inlet).index;
      out = host.port(outlet).index;
    }
  }
  Evaluation at(double dp) {
    Evaluation e(net);
    e.y[out] = kTank;
    e.y[in] = kTank + dp;
    return e;
  }
  double flow(double dp) {
    Evaluation e = at(dp);
    EXPECT_EQ(e.run(*valve), MH_OK);
    EXPECT_EQ(e.residual[out], -e.residual[in]);
    EXPECT_EQ(e.outputs[host.outputs.at("q")], e.residual[in]);
    return e.residual[in];
  }
};

TEST(ReliefValve, IsShutAtAndBelowItsCrackingPressure) {
  ValveFixture f("relief-valve");
  ASSERT_EQ(f.setup_status, MH_OK) << f.host.all_logs();
  EXPECT_EQ(f.host.port("P").role, MH_PORT_FLOW);
  for (double dp : {-5e6, 0.0, 1e6, 19.9e6, kCrack}) EXPECT_EQ(f.flow(dp), 0.0) << dp;
  EXPECT_GT(f.flow(kCrack + 1e3), 0.0);
}

TEST(ReliefValve, FlowFollowsTheOverrideLineToTheCataloguePoint) {
  ValveFixture f("relief-valve");
  ASSERT_EQ(f.setup_status, MH_OK);
  // C from the catalogue point: Q_nom at p_cr + p_ov, where x(1) = 1 - d/2.
  const double c = kQnom / (opening(1.0) * orifice(kCrack + kOverride));
  EXPECT_NEAR(f.flow(kCrack + kOverride), kQnom, 1e-12 * kQnom);
  for (double u : {0.03, 0.1, 0.25, 0.5, 0.8, 1.0, 1.05, 1.2, 3.0}) {
    const double dp = kCrack + u * kOverride;
    const double expected = c * opening(u) * orifice(dp);
    EXPECT_NEAR(f.flow(dp), expected, 1e-12 * kQnom) << u;
    if (u >= kSmooth && u <= 1.0) {  // the override line, shifted by d/2 by the rounding
      EXPECT_NEAR(f.flow(dp), c * (u - kSmooth / 2) * orifice(dp), 1e-12 * kQnom) << u;
    }
  }
  // Fully open it is an orifice: Q proportional to sqrt(dp) (to the smoothing of g).
  const double q1 = f.flow(30e6), q2 = f.flow(40e6);
  EXPECT_NEAR(q2 / q1, std::sqrt(40.0 / 30.0), 1e-4);
}

TEST(ReliefValve, NominalPressureSetsTheCataloguePointWhenGiven) {
  ValveFixture f("relief-valve", kCrack, 25e6, "nominal_pressure");
  ASSERT_EQ(f.setup_status, MH_OK) << f.host.all_logs();
  EXPECT_NEAR(f.flow(25e6), kQnom, 1e-12 * kQnom);
}

// Newton's tangent: the slope dQ/d(dp) is continuous across the corners of the
// opening (u = 0, d, 1, 1 + d): one-sided slopes agree to the differencing error.
TEST(ReliefValve, FlowSlopeIsContinuousAcrossEveryCornerOfTheOpening) {
  ValveFixture f("relief-valve");
  ASSERT_EQ(f.setup_status, MH_OK);
  const double scale = kQnom / kOverride;  // the override line's slope
  for (double u : {0.0, kSmooth, 1.0, 1.0 + kSmooth}) {
    const double dp = kCrack + u * kOverride, h = 1e-6 * kOverride;
    const double left = (f.flow(dp) - f.flow(dp - h)) / h;
    const double right = (f.flow(dp + h) - f.flow(dp)) / h;
    EXPECT_NEAR(left, right, 2e-5 * scale) << u;
    EXPECT_NEAR(f.flow(dp + 1e-3), f.flow(dp - 1e-3), 1e-8 * kQnom) << u;  // continuous
  }
}

TEST(ReliefValve, DissipatesQTimesDpNeverNegative) {
  ValveFixture f("relief-valve");
  ASSERT_EQ(f.setup_status, MH_OK);
  ASSERT_NE(f.valve->api()->energy, nullptr);
  for (double dp = -30e6; dp <= 40e6; dp += 0.37e6) {
    Evaluation e = f.at(dp);
    const mh_subsystem_eval rec = e.record();
    double stored = -1, dissipation = -1;
    ASSERT_EQ(f.valve->api()->energy(f.valve->api(), &rec, &stored, &dissipation), MH_OK);
    EXPECT_EQ(stored, 0.0);
    EXPECT_GE(dissipation, 0.0) << dp;
    EXPECT_NEAR(dissipation, f.flow(dp) * dp, 1e-9 * std::abs(kQnom * dp)) << dp;
  }
}

TEST(ReliefValve, AnalyticJacobianMatchesCentralDifferences) {
  ValveFixture f("relief-valve");
  ASSERT_EQ(f.setup_status, MH_OK);
  double worst = 0.0;
  for (double u : {-0.5, 0.04, 0.5, 1.03, 2.0}) {
    worst = std::max(worst, jacobian_error(*f.valve, f.at(kCrack + u * kOverride)));
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] relief-valve jacobian max relative error %.3g\n", worst);
}

TEST(CheckValve, PassesNoBackflowAndOpensAboveItsCrackingPressure) {
  ValveFixture f("check-valve", 0.5e5);
  ASSERT_EQ(f.setup_status, MH_OK) << f.host.all_logs();
  EXPECT_EQ(f.host.port("A").role, MH_PORT_FLOW);
  for (double dp : {-20e6, -1e5, -1.0, 0.0, 0.5e5}) EXPECT_EQ(f.flow(dp), 0.0) << dp;
  const double c = kQnom / (opening(1.0) * orifice(0.5e5 + kOverride));
  for (double dp : {0.6e5, 1e6, 5e6}) {
    const double u = (dp - 0.5e5) / kOverride;
    EXPECT_NEAR(f.flow(dp), c * opening(u) * orifice(dp), 1e-12 * kQnom) << dp;
    EXPECT_GT(f.flow(dp), 0.0);
  }
}

TEST(CheckValve, WithoutASpringCracksAtZeroAndItsJacobianMatchesCentralDifferences) {
  ValveFixture f("check-valve", 0.0);
  ASSERT_EQ(f.setup_status, MH_OK) << f.host.all_logs();
  EXPECT_EQ(f.flow(-1.0), 0.0);
  EXPECT_GT(f.flow(1.0), 0.0);
  double worst = 0.0;
  for (double dp : {-1e6, 1e4, 1e5, 3e6})
    worst = std::max(worst, jacobian_error(*f.valve, f.at(dp)));
  EXPECT_LT(worst, 1e-6);
}

TEST(PressureValveOptions, BadValuesAreRefusedOnTheirKey) {
  struct Case {
    const char* id;
    const char* key;
    double value;
  };
  for (const Case& c :
       {Case{"relief-valve", "cracking_pressure", 0.0},
        Case{"relief-valve", "cracking_pressure", -1e6},
        Case{"check-valve", "cracking_pressure", -1.0},
        Case{"relief-valve", "override_pressure", 0.0}, Case{"check-valve", "nominal_flow", -1e-3},
        Case{"relief-valve", "smoothing", 0.0}, Case{"relief-valve", "smoothing", 1.5},
        Case{"relief-valve", "transition_pressure", 0.0},
        Case{"relief-valve", "nominal_pressure", 21e6}}) {
    ValveFixture f(c.id);
    f.host.numbers[c.key] = c.value;
    f.host.option_errors.clear();
    Instance again(c.id, f.host);
    EXPECT_EQ(again.setup(), MH_ERROR) << c.id << " " << c.key;
    EXPECT_EQ(f.host.option_errors, std::vector<std::string>{c.key}) << c.id << " " << c.key;
  }
}

}  // namespace
}  // namespace mh::test
