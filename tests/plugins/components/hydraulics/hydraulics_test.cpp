// The hydraulics plugin's components, driven through the C ABI by a fake host
// (fake_host.hpp), without the core: each residual contribution against the
// equations of docs/hydraulics.md evaluated here independently (with the case
// study's numbers, /work/shared/case-studies.md), every analytic jacobian
// against central differences, Eq. 23's effective bulk modulus, the valve's
// reference table, and the option checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "plugins/fake_host.hpp"

namespace mh::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Table 1 of the paper.
constexpr double kPumpPressure = 7.6e6, kTankPressure = 0.1e6;  // Pa
constexpr double kCvd = 2.138e-8;                               // m^3/(s sqrt(Pa) V)
constexpr double kVh2 = 3.14e-5;                                // m^3
constexpr double kThrottleArea = 2.83e-5, kCd = 0.8, kRho = 850.0;
constexpr double kBh = 550e6, kBoil = 1500e6, kBc = 31500e6;  // Pa
constexpr double kEta = 0.88, kD2 = 0.080, kD3 = 0.035, kLength = 1.1;
constexpr double kTau = 4.547e-3;  // s, the case study's Decision
constexpr double kPtr = 2e5;       // Pa
const double kA2 = kPi * kD2 * kD2 / 4.0, kA3 = kPi * (kD2 * kD2 - kD3 * kD3) / 4.0;

// sgn(dp) sqrt|dp|, laminar below 2 bar: the case study's formulas, written out.
double orifice(double dp) {
  if (std::abs(dp) < kPtr) return std::sqrt(kPtr) * dp / kPtr;
  return (dp > 0 ? 1.0 : -1.0) * std::sqrt(std::abs(dp));
}

// Prints a measured analytic-vs-FD jacobian error beside the test's name.
void report(double max_rel_error) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::printf("[ measured ] %s.%s: max relative jacobian error %.3g\n", info->test_suite_name(),
              info->name(), max_rel_error);
}

TEST(HydraulicPlugin, OneLibraryListsItsComponents) {
  std::vector<std::string> ids;
  std::string library;
  for (const ComponentInfo& c : build_plugins().components()) {
    if (c.library.find("monohydra-hydraulics") == std::string::npos) continue;
    ids.push_back(c.id);
    EXPECT_EQ(c.kind, ComponentKind::subsystem);
    EXPECT_EQ(c.abi_version.major, MH_ABI_VERSION_MAJOR);
    EXPECT_EQ(c.abi_version.minor, MH_ABI_VERSION_MINOR);
  }
  EXPECT_EQ(ids, (std::vector<std::string>{
                     "pressure-source", "volume", "throttle", "valve-4-3", "cylinder",
                     "relief-valve", "check-valve", "hydraulic-motor", "valve-table", "flow-source",
                     "hose", "counterbalance-valve", "pilot-check-valve", "variable-pump",
                     "ls-valve-section", "shuttle-valve", "open-centre-valve"}));
}

// ---------------------------------------------------------------------------
// pressure-source

void source_options(FakeHost& host, double pressure) {
  host.numbers = {{"pressure", pressure}};
  host.port_nodes = {{"p", "pump"}};
}

TEST(HydraulicPressureSource, DeclaresAnEffortPortAtItsPressureAndAFlowState) {
  FakeNetwork net;
  FakeHost host(net, "pump");
  source_options(host, kPumpPressure);
  Instance source("pressure-source", host);
  ASSERT_EQ(source.setup(), MH_OK) << host.all_logs();
  const PortRecord& p = host.port("p");
  EXPECT_EQ(p.role, MH_PORT_EFFORT);
  EXPECT_EQ(p.domain, "hydraulic");
  EXPECT_EQ(p.unit, "Pa");
  EXPECT_EQ(p.initial, kPumpPressure);
  EXPECT_EQ(p.abs_tolerance, 1e-2);
  ASSERT_EQ(host.states.size(), 1u);
  EXPECT_EQ(host.states[0].name, "q");
  EXPECT_EQ(host.states[0].unit, "m^3/s");
  EXPECT_EQ(host.states[0].initial, 0.0);
  EXPECT_EQ(host.states[0].abs_tolerance, 1e-10);
}

TEST(HydraulicPressureSource, AddsMinusQToItsNodeAndPMinusPressureToQsRow) {
  FakeNetwork net;
  FakeHost host(net, "pump");
  source_options(host, kPumpPressure);
  Instance source("pressure-source", host);
  ASSERT_EQ(source.setup(), MH_OK);
  const int32_t p = host.port("p").index, q = host.state("q");
  Evaluation e(net);
  e.y[p] = 7.5e6;
  e.y[q] = 3e-4;
  ASSERT_EQ(e.run(source), MH_OK);
  EXPECT_DOUBLE_EQ(e.residual[p], -3e-4);  // q enters the node
  EXPECT_DOUBLE_EQ(e.residual[q], 7.5e6 - kPumpPressure);
}

TEST(HydraulicPressureSource, AnalyticJacobianMatchesCentralDifferences) {
  FakeNetwork net;
  FakeHost host(net, "pump");
  source_options(host, kTankPressure);
  Instance source("pressure-source", host);
  ASSERT_EQ(source.setup(), MH_OK);
  Evaluation e(net);
  e.y[host.port("p").index] = 2e5;
  e.y[host.state("q")] = -1e-4;
  const double err = jacobian_error(source, e);
  EXPECT_LT(err, 1e-6);
  report(err);
}

// ---------------------------------------------------------------------------
// flow-source

TEST(HydraulicFlowSource, AddsMinusItsFlowToItsNodeWhateverThePressureAndWritesItsPower) {
  FakeNetwork net;
  FakeHost host(net, "pump");
  host.numbers = {{"flow", 6e-3}};
  host.port_nodes = {{"p", "supply"}};
  Instance pump("flow-source", host);
  ASSERT_EQ(pump.setup(), MH_OK) << host.all_logs();
  EXPECT_EQ(host.port("p").role, MH_PORT_FLOW);
  EXPECT_TRUE(std::isnan(host.port("p").initial));  // imposes no pressure
  EXPECT_TRUE(host.states.empty());
  const int32_t p = host.port("p").index;
  for (const double pressure : {0.0, 7.6e6, 3.0e7}) {
    Evaluation e(net);
    e.y[p] = pressure;
    ASSERT_EQ(e.run(pump), MH_OK);
    EXPECT_EQ(e.residual[p], -6e-3);  // the flow enters the node
    EXPECT_EQ(e.outputs[host.outputs.at("q")], 6e-3);
    EXPECT_DOUBLE_EQ(e.outputs[host.outputs.at("P")], pressure * 6e-3);
    const double err = jacobian_error(pump, e);  // the row depends on no state
    EXPECT_LT(err, 1e-12);
  }
}

// ---------------------------------------------------------------------------
// volume

void volume_options(FakeHost& host, double volume) {
  host.numbers = {{"volume", volume}, {"bulk_modulus", kBh}, {"fluid_bulk_modulus", kBoil}};
  host.port_nodes = {{"p", "n2"}};
}

TEST(HydraulicVolume, AddsVTimesOneOverBoilPlusOneOverBhTimesPdot) {
  FakeNetwork net;
  FakeHost host(net, "hose");
  volume_options(host, kVh2);
  Instance volume("volume", host);
  ASSERT_EQ(volume.setup(), MH_OK) << host.all_logs();
  const int32_t p = host.port("p").index;
  EXPECT_EQ(host.port("p").role, MH_PORT_FLOW);
  EXPECT_TRUE(std::isnan(host.port("p").initial));  // no initial_pressure: no opinion
  EXPECT_EQ(host.port("p").abs_tolerance, 1e-2);
  Evaluation e(net);
  e.y[p] = 5e6;
  e.ydot[p] = 2.5e7;
  ASSERT_EQ(e.run(volume), MH_OK);
  EXPECT_DOUBLE_EQ(e.residual[p], kVh2 * (1.0 / kBoil + 1.0 / kBh) * 2.5e7);
}

TEST(HydraulicVolume, GivesItsInitialPressureToTheNode) {
  FakeNetwork net;
  FakeHost host(net, "hose");
  volume_options(host, kVh2);
  host.numbers["initial_pressure"] = 5.0243e6;
  host.numbers["tolerance"] = 1e-3;
  Instance volume("volume", host);
  ASSERT_EQ(volume.setup(), MH_OK);
  EXPECT_EQ(host.port("p").initial, 5.0243e6);
  EXPECT_EQ(host.port("p").abs_tolerance, 1e-3);
}

TEST(HydraulicVolume, AnalyticJacobianMatchesCentralDifferences) {
  FakeNetwork net;
  FakeHost host(net, "hose");
  volume_options(host, kVh2);
  Instance volume("volume", host);
  ASSERT_EQ(volume.setup(), MH_OK);
  Evaluation e(net);
  e.y[0] = 3e6;
  e.ydot[0] = -1e7;
  const double err = jacobian_error(volume, e);
  EXPECT_LT(err, 1e-6);
  report(err);
}

// ---------------------------------------------------------------------------
// throttle

const double kCvt = kCd * kThrottleArea * std::sqrt(2.0 / kRho);  // Eq. 25

struct ThrottleFixture {
  FakeNetwork net;
  FakeHost host{net, "throttle"};
  std::unique_ptr<Instance> throttle;
  int32_t a = -1, b = -1;

  explicit ThrottleFixture(const std::string& node_b = "n2") {
    host.numbers = {{"area", kThrottleArea}, {"discharge_coefficient", kCd}, {"density", kRho}};
    host.port_nodes = {{"a", "n1"}, {"b", node_b}};
    throttle = std::make_unique<Instance>("throttle", host);
    EXPECT_EQ(throttle->setup(), MH_OK) << host.all_logs();
    a = host.port("a").index;
    b = host.port("b").index;
  }
  // The flow from a to b at p_a, p_b, from the residual rows (a's row = +Q)
  // after checking b's row is -Q and the output is Q.
  double flow(double p_a, double p_b) {
    Evaluation e(net);
    e.y[a] = p_a;
    e.y[b] = p_b;
    EXPECT_EQ(e.run(*throttle), MH_OK);
    EXPECT_EQ(e.residual[b], -e.residual[a]);
    EXPECT_EQ(e.outputs[host.outputs.at("q")], e.residual[a]);
    return e.residual[a];
  }
};

TEST(HydraulicThrottle, TurbulentFlowAtTenBarIsCvtTimesSqrtDp) {
  ThrottleFixture f;
  const double q = f.flow(6e6, 5e6);
  EXPECT_NEAR(q, kCvt * std::sqrt(1e6), 1e-12 * q);
  EXPECT_NEAR(q, 1.0982e-3, 1e-7);         // C_vt = 1.0982e-6 m^3/(s sqrt(Pa))
  EXPECT_DOUBLE_EQ(f.flow(5e6, 6e6), -q);  // reversed pressure drop, reversed flow
}

TEST(HydraulicThrottle, LaminarBelowTwoBarIsLinearInDp) {
  ThrottleFixture f;
  const double q = f.flow(5.1e6, 5e6);  // 1 bar
  EXPECT_NEAR(q, kCvt * std::sqrt(kPtr) * 1e5 / kPtr, 1e-12 * q);
  EXPECT_NEAR(f.flow(5.05e6, 5e6), 0.5 * q, 1e-12 * q);  // half the drop, half the flow
  EXPECT_NEAR(f.flow(5e6, 5.1e6), -q, 1e-12 * q);
}

TEST(HydraulicThrottle, FlowIsContinuousAtTheTransitionPressure) {
  ThrottleFixture f;
  const double p = 5e6;
  const double at = f.flow(p + kPtr, p);
  const double below = f.flow(p + kPtr * (1.0 - 1e-9), p);
  EXPECT_NEAR(at, kCvt * std::sqrt(kPtr), 1e-12 * at);
  EXPECT_NEAR(below, at, 2e-9 * at);
  EXPECT_NEAR(f.flow(p - kPtr * (1.0 - 1e-9), p), -at, 2e-9 * at);
}

TEST(HydraulicThrottle, TransitionPressureIsAnOption) {
  FakeNetwork net;
  FakeHost host(net, "throttle");
  host.numbers = {{"area", kThrottleArea},
                  {"discharge_coefficient", kCd},
                  {"density", kRho},
                  {"transition_pressure", 1e4}};
  Instance throttle("throttle", host);
  ASSERT_EQ(throttle.setup(), MH_OK);
  Evaluation e(net);
  e.y[host.port("a").index] = 1e5;  // 1 bar: turbulent with a 0.1 bar transition
  ASSERT_EQ(e.run(throttle), MH_OK);
  EXPECT_NEAR(e.residual[host.port("a").index], kCvt * std::sqrt(1e5), 1e-18);
}

TEST(HydraulicThrottle, AnalyticJacobianMatchesCentralDifferencesTurbulentAndLaminar) {
  ThrottleFixture f;
  double worst = 0.0;
  for (const auto& [pa, pb] : std::vector<std::pair<double, double>>{
           {6e6, 5e6}, {5e6, 6e6}, {5.1e6, 5e6}, {5e6, 5.15e6}, {7.6e6, 1e5}, {5e6, 5e6}}) {
    Evaluation e(f.net);
    e.y[f.a] = pa;
    e.y[f.b] = pb;
    const double err = jacobian_error(*f.throttle, e);
    EXPECT_LT(err, 1e-6) << "p_a = " << pa << ", p_b = " << pb;
    worst = std::max(worst, err);
  }
  report(worst);
}

TEST(HydraulicThrottle, BothPortsOnOneNodeCancelInRowAndJacobian) {
  ThrottleFixture f("n1");
  ASSERT_EQ(f.a, f.b);
  ASSERT_EQ(f.host.touched.size(), 1u);
  Evaluation e(f.net);
  e.y[f.a] = 5e6;
  ASSERT_EQ(e.run(*f.throttle), MH_OK);
  EXPECT_EQ(e.residual[f.a], 0.0);
  double d_dy = 0.0, d_dydot = 0.0;
  const mh_subsystem_eval rec = e.record();
  ASSERT_EQ(f.throttle->api()->jacobian(f.throttle->api(), &rec, &d_dy, &d_dydot), MH_OK);
  EXPECT_EQ(d_dy, 0.0);
}

// ---------------------------------------------------------------------------
// valve-4-3

// The four-bar's reference (Eq. 46): 10 V on [1, 2.5) s, -10 V on [5, 8) s.
const std::vector<double> kFourBarReference = {0, 0, 1, 0, 1,   10, 2.5, 10, 2.5,
                                               0, 5, 0, 5, -10, 8,  -10, 8,  0};

struct ValveFixture {
  FakeNetwork net;
  FakeHost host{net, "valve"};
  std::unique_ptr<Instance> valve;
  int32_t P = -1, T = -1, A = -1, B = -1, U = -1;

  explicit ValveFixture(const std::vector<double>& reference = kFourBarReference,
                        double limit = kNaN) {
    host.numbers = {{"flow_coefficient", kCvd}, {"time_constant", kTau}};
    if (!std::isnan(limit)) host.numbers["spool_limit"] = limit;
    host.tables["reference"] = {2u, reference};
    host.port_nodes = {{"P", "pump"}, {"T", "tank"}, {"A", "n1"}, {"B", "n3"}};
    valve = std::make_unique<Instance>("valve-4-3", host);
    EXPECT_EQ(valve->setup(), MH_OK) << host.all_logs();
    P = host.port("P").index;
    T = host.port("T").index;
    A = host.port("A").index;
    B = host.port("B").index;
    U = host.state("U");
  }
  Evaluation at(double u, double p1, double p3, double t = 0.0) const {
    Evaluation e(net);
    e.t = t;
    e.y[P] = kPumpPressure;
    e.y[T] = kTankPressure;
    e.y[A] = p1;
    e.y[B] = p3;
    e.y[U] = u;
    return e;
  }
  double reference(double t) {
    Evaluation e = at(0.0, 5e6, 3.5e6, t);
    EXPECT_EQ(e.run(*valve), MH_OK);
    return e.outputs[host.outputs.at("U_ref")];
  }
};

TEST(HydraulicValve43, DeclaresFourFlowPortsAndTheSpoolState) {
  ValveFixture f;
  for (const char* key : {"P", "T", "A", "B"}) {
    EXPECT_EQ(f.host.port(key).role, MH_PORT_FLOW) << key;
    EXPECT_TRUE(std::isnan(f.host.port(key).initial)) << key;
  }
  ASSERT_EQ(f.host.states.size(), 1u);
  EXPECT_EQ(f.host.states[0].unit, "V");
  EXPECT_EQ(f.host.states[0].initial, 0.0);
  EXPECT_EQ(f.host.states[0].abs_tolerance, 1e-7);
}

TEST(HydraulicValve43, TheSpoolIsAControlSignalOverTheReferenceRange) {
  ValveFixture f;  // spool_limit absent: the case studies' 10 V
  const StateRecord& u = f.host.state_record("U");
  EXPECT_EQ(u.role, MH_ROLE_CONTROL_SIGNAL);
  EXPECT_EQ(u.range_min, -10.0);
  EXPECT_EQ(u.range_max, 10.0);
  // The reference output is a plain signal.
  EXPECT_EQ(f.host.output("U_ref").kind, static_cast<uint32_t>(MH_OUTPUT_SIGNAL));
  EXPECT_EQ(f.host.output("U_ref").role, "");

  ValveFixture g({0.0, 12.0, 1.0, -30.0}, 5.0);  // spool_limit 5 V
  EXPECT_EQ(g.host.state_record("U").range_min, -5.0);
  EXPECT_EQ(g.host.state_record("U").range_max, 5.0);
}

// The case study's Q_d1 (into V1 = A) and Q_3d (out of V3 = B), as printed there.
double q_d1(double u, double p1) {
  return u >= 0 ? kCvd * u * orifice(kPumpPressure - p1) : kCvd * u * orifice(p1 - kTankPressure);
}
double q_3d(double u, double p3) {
  return u >= 0 ? kCvd * u * orifice(p3 - kTankPressure) : kCvd * u * orifice(kPumpPressure - p3);
}

// dp1/dt = Be1/V1 (Q_d1 - Q_t) and dp3/dt = Be3/V3 (A3 sdot - Q_3d): the valve
// adds -Q_d1 to p1's row and +Q_3d to p3's row; the pump loses what A gains
// (U > 0) or what B gains (U < 0), the tank receives the rest.
void expect_case_study_flows(const ValveFixture& f, double u, double p1, double p3) {
  Evaluation e = f.at(u, p1, p3);
  ASSERT_EQ(e.run(*f.valve), MH_OK);
  const double d1 = q_d1(u, p1), d3 = q_3d(u, p3);
  const double tol = 1e-12 * (std::abs(d1) + std::abs(d3)) + 1e-20;
  EXPECT_NEAR(e.residual[f.A], -d1, tol) << "U = " << u;
  EXPECT_NEAR(e.residual[f.B], d3, tol) << "U = " << u;
  if (u >= 0) {
    EXPECT_NEAR(e.residual[f.P], d1, tol);   // P -> A
    EXPECT_NEAR(e.residual[f.T], -d3, tol);  // B -> T
  } else {
    EXPECT_NEAR(e.residual[f.P], -d3, tol);  // P -> B (Q_3d < 0)
    EXPECT_NEAR(e.residual[f.T], d1, tol);   // A -> T (Q_d1 < 0)
  }
  EXPECT_NEAR(e.residual[f.P] + e.residual[f.T] + e.residual[f.A] + e.residual[f.B], 0.0, tol);
}

TEST(HydraulicValve43, PositiveSpoolOpensPumpToAAndBToTankAsQd1AndQ3d) {
  ValveFixture f;
  expect_case_study_flows(f, 4.0, 5.0243e6, 3.5e6);
  Evaluation e = f.at(4.0, 5.0243e6, 3.5e6);
  ASSERT_EQ(e.run(*f.valve), MH_OK);
  EXPECT_LT(e.residual[f.A], 0.0);  // fluid enters V1
  EXPECT_GT(e.residual[f.B], 0.0);  // fluid leaves V3
  EXPECT_NEAR(e.residual[f.A], -kCvd * 4.0 * std::sqrt(kPumpPressure - 5.0243e6), 1e-15);
}

TEST(HydraulicValve43, NegativeSpoolCrossesOverToAToTankAndPumpToB) {
  ValveFixture f;
  expect_case_study_flows(f, -4.0, 5.0243e6, 3.5e6);
  Evaluation e = f.at(-4.0, 5.0243e6, 3.5e6);
  ASSERT_EQ(e.run(*f.valve), MH_OK);
  EXPECT_GT(e.residual[f.A], 0.0);  // fluid leaves V1
  EXPECT_LT(e.residual[f.B], 0.0);  // fluid enters V3
  EXPECT_NEAR(e.residual[f.A], kCvd * 4.0 * std::sqrt(5.0243e6 - kTankPressure), 1e-15);
}

TEST(HydraulicValve43, BackflowAndLaminarFlowsFollowTheCaseStudyFormulas) {
  ValveFixture f;
  expect_case_study_flows(f, 10.0, 8e6, 0.05e6);     // A above the pump: flows back to P
  expect_case_study_flows(f, -10.0, 0.05e6, 7.7e6);  // both drops reversed
  expect_case_study_flows(f, 2.5, 7.5e6, 0.15e6);    // both laminar (1 and 0.5 bar)
  expect_case_study_flows(f, -2.5, 0.2e6, 7.45e6);   // both laminar, crossed over
}

TEST(HydraulicValve43, FlowsVanishContinuouslyAsTheSpoolCrossesZeroEitherWay) {
  ValveFixture f;
  for (double u : {1e-9, -1e-9}) {
    Evaluation e = f.at(u, 5e6, 3.5e6);
    ASSERT_EQ(e.run(*f.valve), MH_OK);
    for (int32_t node : {f.P, f.T, f.A, f.B}) EXPECT_LT(std::abs(e.residual[node]), 1e-12);
  }
  Evaluation zero = f.at(0.0, 5e6, 3.5e6);
  ASSERT_EQ(zero.run(*f.valve), MH_OK);
  for (int32_t node : {f.P, f.T, f.A, f.B}) EXPECT_EQ(zero.residual[node], 0.0);
}

TEST(HydraulicValve43, SpoolRowIsTauUdotMinusReferenceMinusU) {
  ValveFixture f;
  Evaluation e = f.at(3.0, 5e6, 3.5e6, 2.0);  // U_ref = 10 at t = 2 s
  e.ydot[f.U] = 500.0;
  ASSERT_EQ(e.run(*f.valve), MH_OK);
  EXPECT_DOUBLE_EQ(e.residual[f.U], kTau * 500.0 - (10.0 - 3.0));
  EXPECT_EQ(e.outputs[f.host.outputs.at("U_ref")], 10.0);
}

TEST(HydraulicValve43, AnalyticJacobianMatchesCentralDifferencesInBothDirections) {
  ValveFixture f;
  struct Point {
    double u, p1, p3, t;
  };
  double worst = 0.0;
  for (const Point& x : {Point{4.0, 5.0243e6, 3.5e6, 2.0},   // U > 0, turbulent
                         Point{-4.0, 5.0243e6, 3.5e6, 6.0},  // U < 0, turbulent
                         Point{7.0, 7.5e6, 0.15e6, 1.5},     // U > 0, both laminar
                         Point{-7.0, 0.2e6, 7.45e6, 7.0},    // U < 0, both laminar
                         Point{2.0, 8e6, 0.05e6, 0.5},       // backflow A -> P, laminar B -> T
                         Point{-0.3, 3e6, 7.9e6, 9.0}}) {    // backflow B -> P
    Evaluation e = f.at(x.u, x.p1, x.p3, x.t);
    e.ydot[f.U] = 100.0;
    e.ydot[f.A] = 1e6;
    const double err = jacobian_error(*f.valve, e);
    EXPECT_LT(err, 1e-6) << "U = " << x.u << ", p1 = " << x.p1 << ", p3 = " << x.p3;
    worst = std::max(worst, err);
  }
  report(worst);
}

// ---------------------------------------------------------------------------
// The reference table

TEST(HydraulicTimeTable, InterpolatesLinearlyBetweenRowsAndHoldsTheEnds) {
  ValveFixture f({1.0, 2.0, 3.0, 6.0, 4.0, 4.0});
  EXPECT_EQ(f.reference(0.0), 2.0);  // before the first row: the first value
  EXPECT_EQ(f.reference(1.0), 2.0);
  EXPECT_DOUBLE_EQ(f.reference(1.5), 3.0);
  EXPECT_DOUBLE_EQ(f.reference(2.5), 5.0);
  EXPECT_DOUBLE_EQ(f.reference(3.5), 5.0);
  EXPECT_EQ(f.reference(4.0), 4.0);
  EXPECT_EQ(f.reference(100.0), 4.0);       // after the last row: the last value
  EXPECT_TRUE(f.host.time_events.empty());  // no repeated time: no jump
}

TEST(HydraulicTimeTable, RepeatedTimeIsARightContinuousJumpDeclaredAsATimeEvent) {
  ValveFixture f;
  EXPECT_EQ(f.reference(0.999999), 0.0);
  EXPECT_EQ(f.reference(1.0), 10.0);  // the later row holds from the jump on
  EXPECT_EQ(f.reference(2.4999), 10.0);
  EXPECT_EQ(f.reference(2.5), 0.0);
  EXPECT_EQ(f.reference(5.0), -10.0);
  EXPECT_EQ(f.reference(7.9999), -10.0);
  EXPECT_EQ(f.reference(8.0), 0.0);
  EXPECT_EQ(f.reference(10.0), 0.0);
  EXPECT_EQ(f.host.time_events, (std::vector<double>{1.0, 2.5, 5.0, 8.0}));
}

TEST(HydraulicTimeTable, ReferenceIsClippedToTheSpoolLimit) {
  ValveFixture f({0.0, 12.0, 1.0, -30.0});
  EXPECT_EQ(f.reference(0.0), 10.0);
  EXPECT_EQ(f.reference(1.0), -10.0);
  EXPECT_DOUBLE_EQ(f.reference(0.5), -9.0);  // inside the limit: untouched
  ValveFixture g({0.0, 12.0, 1.0, -30.0}, 5.0);
  EXPECT_EQ(g.reference(0.0), 5.0);
  EXPECT_EQ(g.reference(1.0), -5.0);
}

// ---------------------------------------------------------------------------
// cylinder

// The four-bar's cylinder: from ground point G = (0, -2) to F = (1, -1), s0 = sqrt(2).
struct CylinderFixture {
  FakeNetwork net;
  FakeHost host{net, "cylinder"};
  std::unique_ptr<Instance> cylinder;
  int32_t A = -1, B = -1;
  mh_status setup_status = MH_OK;

  explicit CylinderFixture(double length = kLength, bool end_stops = false) {
    host.numbers = {
        {"piston_diameter", kD2},      {"rod_diameter", kD3},         {"length", length},
        {"chamber_bulk_modulus", kBc}, {"fluid_bulk_modulus", kBoil}, {"efficiency", kEta}};
    if (end_stops) {
      host.numbers["end_stop_stiffness"] = 1e8;
      host.numbers["end_stop_damping"] = 2e5;
      host.numbers["end_stop_depth"] = 1e-3;
    }
    host.point_positions = {{"a", {0.0, -2.0, 0.0}}, {"b", {1.0, -1.0, 0.0}}};
    host.port_nodes = {{"A", "n2"}, {"B", "n3"}};
    cylinder = std::make_unique<Instance>("cylinder", host);
    setup_status = cylinder->setup();
    if (setup_status == MH_OK) {
      A = host.port("A").index;
      B = host.port("B").index;
    }
  }
  // Rod end at G + s (cos 45, sin 45) moving at sdot along the axis.
  Evaluation at(double s, double sdot, double p2, double p3) const {
    Evaluation e(net, 2);
    const double c = std::sqrt(0.5);
    e.point_p = {0.0, -2.0, 0.0, s * c, -2.0 + s * c, 0.0};
    e.point_v = {0.0, 0.0, 0.0, sdot * c, sdot * c, 0.0};
    e.y[A] = p2;
    e.y[B] = p3;
    return e;
  }
};

const double kS0 = std::sqrt(2.0);

TEST(HydraulicCylinder, ChamberRowsAreStorageOfA2l2AndA3l3PlusThePistonFlows) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK) << f.host.all_logs();
  const double s = kS0 + 0.1, sdot = 0.05, p2 = 5e6, p3 = 3.5e6;
  Evaluation e = f.at(s, sdot, p2, p3);
  e.ydot[f.A] = 2e6;
  e.ydot[f.B] = -3e6;
  ASSERT_EQ(e.run(*f.cylinder), MH_OK);
  // l2_0 = s0 - l, l3_0 = l - l2_0; extending by 0.1 m grows l2 and shrinks l3.
  const double l2 = (kS0 - kLength) + 0.1, l3 = (kLength - (kS0 - kLength)) - 0.1;
  const double k = 1.0 / kBoil + 1.0 / kBc;
  EXPECT_NEAR(e.residual[f.A], kA2 * l2 * k * 2e6 + kA2 * sdot, 1e-15);
  EXPECT_NEAR(e.residual[f.B], kA3 * l3 * k * -3e6 - kA3 * sdot, 1e-15);
  EXPECT_NEAR(e.outputs[f.host.outputs.at("s")], s, 1e-14);
  EXPECT_NEAR(e.outputs[f.host.outputs.at("sdot")], sdot, 1e-14);
}

TEST(HydraulicCylinder, PushesThePointsApartAlongTheAxisWithPistonForce) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  // The four-bar's static state: p2 = (F_s0 + p3 A3) / A2 gives F = F_s0.
  const double fs0 = 11029.38, p3 = 3.5e6, p2 = (fs0 + p3 * kA3) / kA2;
  EXPECT_NEAR(p2, 5.0243e6, 100.0);
  Evaluation e = f.at(kS0, 0.0, p2, p3);
  ASSERT_EQ(e.run(*f.cylinder), MH_OK);
  const double c = std::sqrt(0.5);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(e.point_f[3 + i], fs0 * c, 1e-8);  // on b: +F e
    EXPECT_NEAR(e.point_f[i], -fs0 * c, 1e-8);     // on a: -F e
  }
  EXPECT_EQ(e.point_f[2], 0.0);
  EXPECT_NEAR(e.outputs[f.host.outputs.at("Fs")], fs0, 1e-8);
}

TEST(HydraulicCylinder, FrictionIsZeroAtRestAndOpposesMotion) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  const double p2 = 5e6, p3 = 3.5e6, piston = p2 * kA2 - p3 * kA3;
  auto force = [&](double sdot) {
    Evaluation e = f.at(kS0 + 0.2, sdot, p2, p3);
    EXPECT_EQ(e.run(*f.cylinder), MH_OK);
    return e.outputs[f.host.outputs.at("Fs")];
  };
  EXPECT_NEAR(force(0.0), piston, 1e-12 * piston);
  for (double sdot : {0.001, 0.01, 0.3, -0.001, -0.3}) {
    const double friction = (1.0 - kEta) * std::abs(piston) * std::tanh(sdot / 0.01);
    EXPECT_NEAR(force(sdot), piston - friction, 1e-9 * piston) << sdot;
    // Opposes the motion: less push while extending, more while retracting.
    if (sdot > 0) {
      EXPECT_LT(force(sdot), piston);
    } else {
      EXPECT_GT(force(sdot), piston);
    }
  }
  // Fast motion: the full (1 - eta) share of the piston force.
  EXPECT_NEAR(force(1.0), kEta * piston, 1e-6 * piston);
}

TEST(HydraulicCylinder, DissipatesFrictionTimesSpeedInBothDirections) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  ASSERT_NE(f.cylinder->api()->energy, nullptr);
  const double p2 = 2e6, p3 = 6e6, piston = p2 * kA2 - p3 * kA3;  // pulling: piston < 0
  for (double sdot : {0.0, 0.02, -0.02}) {
    Evaluation e = f.at(kS0, sdot, p2, p3);
    const mh_subsystem_eval rec = e.record();
    double stored = -1.0, dissipation = -1.0;
    ASSERT_EQ(f.cylinder->api()->energy(f.cylinder->api(), &rec, &stored, &dissipation), MH_OK);
    EXPECT_EQ(stored, 0.0);
    EXPECT_GE(dissipation, 0.0);
    EXPECT_NEAR(dissipation, (1.0 - kEta) * std::abs(piston) * std::tanh(sdot / 0.01) * sdot, 1e-9);
  }
}

TEST(HydraulicCylinder, AnalyticJacobianMatchesCentralDifferences) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  double worst = 0.0;
  for (double ds : {-0.2, 0.0, 0.3}) {
    Evaluation e = f.at(kS0 + ds, 0.04, 5e6, 3.5e6);
    e.ydot[f.A] = 1e7;
    e.ydot[f.B] = -2e6;
    worst = std::max(worst, jacobian_error(*f.cylinder, e));
  }
  EXPECT_LT(worst, 1e-6);
  report(worst);
}

// point_force_jacobian and coupling_jacobian against
// central differences of evaluate in the points' motion and the pressures, at
// points a and b moving as given; the largest error relative to the scales
// (force derivatives: force_scale, N/m) goes to `worst`.
void point_and_coupling_error(CylinderFixture& f, const std::vector<double>& point_p,
                              const std::vector<double>& point_v, double& worst,
                              double force_scale = 1e5) {
  const mh_subsystem* api = f.cylinder->api();
  ASSERT_NE(api->point_force_jacobian, nullptr);
  ASSERT_NE(api->coupling_jacobian, nullptr);
  const std::vector<int32_t>& touched = f.host.touched;
  const size_t n = touched.size();
  Evaluation e = f.at(kS0, 0.0, 5e6, 3.5e6);
  e.num_touched = n;
  e.point_p = point_p;
  e.point_v = point_v;
  e.ydot[f.A] = 1e7;
  e.ydot[f.B] = -2e6;
  std::vector<double> dF_dp(36, 0.0), dF_dv(36, 0.0), dR_dp(n * 6, 0.0), dR_dv(n * 6, 0.0),
      dF_dy(6 * n, 0.0), dF_dydot(6 * n, 0.0);
  {
    const mh_subsystem_eval rec = e.record();
    ASSERT_EQ(api->point_force_jacobian(api, &rec, dF_dp.data(), dF_dv.data()), MH_OK);
    ASSERT_EQ(api->coupling_jacobian(api, &rec, dR_dp.data(), dR_dv.data(), dF_dy.data(),
                                     dF_dydot.data()),
              MH_OK);
  }
  const auto check = [&](double analytic, double fd, double scale) {
    worst = std::max(worst, std::abs(analytic - fd) / std::max(scale, 1e-300));
  };
  // In the points' motion: forces (3P x 3P) and rows (n x 3P), both column-major.
  for (int level = 0; level < 2; ++level) {
    std::vector<double>& x = level == 0 ? e.point_p : e.point_v;
    for (size_t c = 0; c < 6; ++c) {
      const double x0 = x[c], h = 1e-7;
      x[c] = x0 + h;
      ASSERT_EQ(e.run(*f.cylinder), MH_OK);
      const std::vector<double> f_plus = e.point_f, r_plus = e.residual;
      x[c] = x0 - h;
      ASSERT_EQ(e.run(*f.cylinder), MH_OK);
      x[c] = x0;
      for (size_t r = 0; r < 6; ++r)
        check((level == 0 ? dF_dp : dF_dv)[c * 6 + r], (f_plus[r] - e.point_f[r]) / (2 * h),
              force_scale);
      for (size_t a = 0; a < n; ++a) {
        const size_t row = static_cast<size_t>(touched[a]);
        check((level == 0 ? dR_dp : dR_dv)[c * n + a], (r_plus[row] - e.residual[row]) / (2 * h),
              1e-3);
      }
    }
  }
  // In the pressures: forces (3P x n column-major).
  for (size_t b = 0; b < n; ++b) {
    const size_t i = static_cast<size_t>(touched[b]);
    const double y0 = e.y[i], h = 10.0;
    e.y[i] = y0 + h;
    ASSERT_EQ(e.run(*f.cylinder), MH_OK);
    const std::vector<double> f_plus = e.point_f;
    e.y[i] = y0 - h;
    ASSERT_EQ(e.run(*f.cylinder), MH_OK);
    e.y[i] = y0;
    for (size_t r = 0; r < 6; ++r) {
      check(dF_dy[b * 6 + r], (f_plus[r] - e.point_f[r]) / (2 * h), 1e-3);
      EXPECT_EQ(dF_dydot[b * 6 + r], 0.0);  // the force has no pressure rates in it
    }
  }
}

// On a general 3D configuration (both points moving, off the fixture's diagonal).
TEST(HydraulicCylinder, PointAndCouplingJacobiansMatchCentralDifferences) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  double worst = 0.0;
  for (double sdot : {0.004, -0.03})
    point_and_coupling_error(f, {0.05, -1.98, 0.01, 1.1, -0.92, -0.02},
                             {0.01, -0.02, 0.003, sdot, 0.7 * sdot, 0.002}, worst);
  EXPECT_LT(worst, 1e-6);
  report(worst);
}

// With end stops on, pressed into either stop (inside the depth over which the
// damping comes in, and past it): the stops' stiffness and damping are in
// the point-force derivatives, and an emptied chamber no longer moves its row.
TEST(HydraulicCylinder, PointAndCouplingJacobiansIncludeTheEndStops) {
  CylinderFixture f(kLength, true);
  ASSERT_EQ(f.setup_status, MH_OK);
  const double a[3] = {0.05, -1.98, 0.01};
  const double d[3] = {1.05, 1.06, -0.03};
  const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  double worst = 0.0;
  // The stroke spans [l, 2 l]: pressed 0.4 mm and 3 mm past each end.
  for (double s : {2 * kLength + 4e-4, 2 * kLength + 3e-3, kLength - 4e-4, kLength - 3e-3})
    for (double sdot : {0.02, -0.01}) {
      std::vector<double> p(6), v(6);
      for (int i = 0; i < 3; ++i) {
        p[i] = a[i];
        p[3 + i] = a[i] + s * d[i] / norm;
        v[i] = 0.001 * (i + 1);
        v[3 + i] = v[i] + sdot * d[i] / norm + 0.002 * (i == 2 ? 1.0 : 0.0);
      }
      point_and_coupling_error(f, p, v, worst, 1e8);  // the stops' stiffness
    }
  EXPECT_LT(worst, 1e-6);
  report(worst);
}

TEST(HydraulicCylinder, InitialLengthOutsideTheCylinderIsRefusedOnLength) {
  for (double length : {1.5, 0.6}) {  // l2_0 = s0 - l < 0; l3_0 = 2 l - s0 < 0
    CylinderFixture f(length);
    EXPECT_EQ(f.setup_status, MH_ERROR) << length;
    ASSERT_EQ(f.host.option_errors, std::vector<std::string>{"length"}) << length;
    EXPECT_NE(f.host.expected[0].find("s0 = 1.41421 m"), std::string::npos) << f.host.expected[0];
  }
}

TEST(HydraulicCylinder, StrokeLeavingTheCylinderIsAnErrorNamingSAndTheRange) {
  CylinderFixture f;
  ASSERT_EQ(f.setup_status, MH_OK);
  // The stroke range is [s0 - l2_0, s0 + l3_0] = [l, 2 l] = [1.1, 2.2] m.
  EXPECT_EQ(f.at(1.1001, 0.0, 5e6, 3.5e6).run(*f.cylinder), MH_OK);
  EXPECT_EQ(f.at(2.1999, 0.0, 5e6, 3.5e6).run(*f.cylinder), MH_OK);
  for (double s : {2.3, 1.0}) {
    f.host.logs.clear();
    Evaluation e = f.at(s, 0.0, 5e6, 3.5e6);
    EXPECT_EQ(e.run(*f.cylinder), MH_ERROR) << s;
    const std::string log = f.host.all_logs();
    EXPECT_NE(log.find("s = " + std::string(s > 2 ? "2.3" : "1") + " m"), std::string::npos) << log;
    EXPECT_NE(log.find("[1.1, 2.2] m"), std::string::npos) << log;
  }
}

// ---------------------------------------------------------------------------
// Eq. 23: the node's capacitance V2 / Be2 is the sum of its sub-volumes'.

TEST(HydraulicNode, HoseAndChamberCapacitancesSumToV2OverBe2OfEq23) {
  FakeNetwork net;
  FakeHost hose_host(net, "hose2");
  volume_options(hose_host, kVh2);
  Instance hose("volume", hose_host);
  ASSERT_EQ(hose.setup(), MH_OK);
  FakeHost cyl_host(net, "cylinder");
  cyl_host.numbers = {{"piston_diameter", kD2},      {"rod_diameter", kD3},
                      {"length", kLength},           {"chamber_bulk_modulus", kBc},
                      {"fluid_bulk_modulus", kBoil}, {"efficiency", kEta}};
  cyl_host.point_positions = {{"a", {0.0, -2.0, 0.0}}, {"b", {1.0, -1.0, 0.0}}};
  cyl_host.port_nodes = {{"A", "n2"}, {"B", "n3"}};
  Instance cylinder("cylinder", cyl_host);
  ASSERT_EQ(cylinder.setup(), MH_OK);
  const int32_t p2 = hose_host.port("p").index;
  ASSERT_EQ(cyl_host.port("A").index, p2);  // one node, one state

  for (double ds : {0.0, 0.25}) {
    Evaluation e(net, 2);
    const double s = kS0 + ds, c = std::sqrt(0.5);
    e.point_p = {0.0, -2.0, 0.0, s * c, -2.0 + s * c, 0.0};
    e.ydot[p2] = 1.0;  // the row then holds the node's capacitance
    ASSERT_EQ(e.run(hose), MH_OK);
    const double hose_row = e.residual[p2];
    ASSERT_EQ(e.run(cylinder), MH_OK);
    const double capacitance = hose_row + e.residual[p2];
    // Case study: V2 = V_h2 + A2 l2, 1/Be2 = 1/B_oil + (V_h2/B_h + A2 l2/B_c) / V2.
    const double l2 = kS0 - kLength + ds, v2 = kVh2 + kA2 * l2;
    const double be2 = 1.0 / (1.0 / kBoil + (kVh2 / kBh + kA2 * l2 / kBc) / v2);
    EXPECT_NEAR(capacitance, v2 / be2, 1e-12 * v2 / be2) << ds;
  }
}

// ---------------------------------------------------------------------------
// Options

struct BadOption {
  const char* component;
  const char* key;
  double value;  // NaN: leave the table case to `table`
  std::vector<double> table;
};

void base_options(const std::string& component, FakeHost& host) {
  if (component == "pressure-source") {
    host.numbers = {{"pressure", kPumpPressure}};
  } else if (component == "flow-source") {
    host.numbers = {{"flow", 6e-3}};
  } else if (component == "volume") {
    host.numbers = {{"volume", kVh2}, {"bulk_modulus", kBh}, {"fluid_bulk_modulus", kBoil}};
  } else if (component == "throttle") {
    host.numbers = {{"area", kThrottleArea}, {"discharge_coefficient", kCd}, {"density", kRho}};
  } else if (component == "valve-4-3") {
    host.numbers = {{"flow_coefficient", kCvd}, {"time_constant", kTau}};
    host.tables["reference"] = {2u, kFourBarReference};
  } else if (component == "cylinder") {
    host.numbers = {{"piston_diameter", kD2},      {"rod_diameter", kD3},
                    {"length", kLength},           {"chamber_bulk_modulus", kBc},
                    {"fluid_bulk_modulus", kBoil}, {"efficiency", kEta}};
    host.point_positions = {{"a", {0.0, -2.0, 0.0}}, {"b", {1.0, -1.0, 0.0}}};
  }
}

TEST(HydraulicOptions, EveryComponentSetsUpWithTheCaseStudysOptions) {
  for (const char* id :
       {"pressure-source", "flow-source", "volume", "throttle", "valve-4-3", "cylinder"}) {
    FakeNetwork net;
    FakeHost host(net, id);
    base_options(id, host);
    Instance instance(id, host);
    ASSERT_NE(instance.api(), nullptr) << id;
    EXPECT_EQ(instance.setup(), MH_OK) << id << ": " << host.all_logs();
    EXPECT_TRUE(host.option_errors.empty()) << id;
  }
}

TEST(HydraulicOptions, BadValuesAreRefusedOnTheirKey) {
  const std::vector<BadOption> cases = {
      {"pressure-source", "pressure", -1.0, {}},
      {"pressure-source", "tolerance", 0.0, {}},
      {"flow-source", "flow", -1e-3, {}},
      {"volume", "volume", -1e-5, {}},
      {"volume", "volume", 0.0, {}},
      {"volume", "bulk_modulus", 0.0, {}},
      {"volume", "fluid_bulk_modulus", -1500e6, {}},
      {"throttle", "area", 0.0, {}},
      {"throttle", "discharge_coefficient", -0.8, {}},
      {"throttle", "density", 0.0, {}},
      {"throttle", "transition_pressure", -2e5, {}},
      {"valve-4-3", "flow_coefficient", 0.0, {}},
      {"valve-4-3", "time_constant", 0.0, {}},
      {"valve-4-3", "spool_limit", -10.0, {}},
      {"valve-4-3", "reference", kNaN, {0, 0, 2, 10, 1, 0}},  // unsorted
      {"valve-4-3", "reference", kNaN, {}},                   // no row
      {"cylinder", "piston_diameter", 0.0, {}},
      {"cylinder", "rod_diameter", 0.08, {}},  // = piston
      {"cylinder", "rod_diameter", 0.09, {}},  // > piston
      {"cylinder", "efficiency", 1.2, {}},
      {"cylinder", "efficiency", 0.0, {}},
      {"cylinder", "chamber_bulk_modulus", 0.0, {}},
      {"cylinder", "friction_velocity", 0.0, {}},
  };
  for (const BadOption& c : cases) {
    FakeNetwork net;
    FakeHost host(net, c.component);
    base_options(c.component, host);
    if (std::isnan(c.value))
      host.tables[c.key] = {2u, c.table};
    else
      host.numbers[c.key] = c.value;
    Instance instance(c.component, host);
    EXPECT_EQ(instance.setup(), MH_ERROR) << c.component << " " << c.key << " = " << c.value;
    EXPECT_EQ(host.option_errors, std::vector<std::string>{c.key})
        << c.component << " " << c.key << " = " << c.value;
    for (const std::string& text : host.expected) EXPECT_FALSE(text.empty());
  }
}

TEST(HydraulicOptions, UnsortedReferenceNamesTheRowThatGoesBack) {
  FakeNetwork net;
  FakeHost host(net, "valve");
  base_options("valve-4-3", host);
  host.tables["reference"] = {2u, {0, 0, 2, 10, 1, 0}};
  Instance valve("valve-4-3", host);
  ASSERT_EQ(valve.setup(), MH_ERROR);
  ASSERT_EQ(host.expected.size(), 1u);
  EXPECT_NE(host.expected[0].find("sorted by time"), std::string::npos) << host.expected[0];
  EXPECT_NE(host.expected[0].find("row 3"), std::string::npos) << host.expected[0];
}

}  // namespace
}  // namespace mh::test
