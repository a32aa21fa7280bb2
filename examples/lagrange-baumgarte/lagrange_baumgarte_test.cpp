// The example formulation's unit test, against the installed test host alone
// (monohydra::testhost, docs/plugin-guide.md): on the free four-bar (the
// paper's Fig. 4 without its cylinder) Baumgarte's terms keep the loop closed
// within a bound where plain index-1 multipliers let it open, the energy
// balance holds, the analytic tangent equals differences of the residual,
// and every check of `monohydra check` passes, there and on the example
// model the formulation declares.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <monohydra/testhost.hpp>
#include <string>

namespace {

namespace th = monohydra::testhost;

const th::Host& host() {
  static const th::Host h(LAGRANGE_BAUMGARTE_LIBRARY, "lagrange-baumgarte");
  return h;
}

// The example model the library declares (the four-bar linkage, falling
// under gravity) with `formulation` and a longer run: three joint
// coordinates, one revolute cut joint E, two constraint rows, one degree of
// freedom.
th::Model free_fourbar(const std::string& formulation) {
  const std::string example = host().example_model();
  return th::Model::text(example.substr(0, example.find("formulation:")) +
                             "formulation: " + formulation +
                             "\nsolver: {dt: 0.001, t_end: 10, max_iterations: 25, "
                             "tol_position: 1e-7}\n",
                         "free-fourbar.yaml");
}

double max_of(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// 10 s of the falling four-bar at 10 ms (1000 steps): the largest |Phi|.
double max_phi(const std::string& options) {
  const th::Series s =
      host().run(free_fourbar("{name: lagrange-baumgarte" + options + "}"), 1000, 1e-2);
  EXPECT_TRUE(s.ok) << s.status;
  return max_of(s.column("phi_norm"));
}

TEST(LagrangeBaumgarte, KeepsTheLoopClosedWithinABoundWherePlainMultipliersDrift) {
  const double stabilized = max_phi("");
  const double plain = max_phi(", alpha: 0, beta: 0");
  std::printf("  max |Phi| over 10 s at 10 ms: Baumgarte %.2e, plain %.2e\n", stabilized, plain);
  EXPECT_LT(stabilized, 1e-4);         // m: the loop stays closed
  EXPECT_GT(plain, 5.0 * stabilized);  // and the stabilization is what closes it
}

TEST(LagrangeBaumgarte, ConservesEnergyOnTheFallingFourBar) {
  const th::Series s = host().run(free_fourbar("{name: lagrange-baumgarte}"), 2000);
  ASSERT_TRUE(s.ok) << s.status;
  // Nothing dissipates: KE + PE stays at its start (drift, J) while the
  // mechanism converts hundreds of joules of potential into kinetic energy.
  EXPECT_GT(max_of(s.column("kinetic_energy")), 100.0);
  EXPECT_LT(max_of(s.column("drift")), 1e-2 * max_of(s.column("kinetic_energy")));
}

TEST(LagrangeBaumgarte, AnalyticTangentEqualsDifferencesOfItsResidual) {
  const th::TangentComparison t = host().tangent(free_fourbar("{name: lagrange-baumgarte}"), 200);
  ASSERT_TRUE(t.failure.empty()) << t.failure;
  std::printf("  tangent: max error %.2e (%s)\n", t.max_error, t.worst.c_str());
  EXPECT_LT(t.max_error, 1e-5) << t.worst;
}

// Without a model, `monohydra check` runs the formulation on the example
// model it declares (MONOHYDRA_FORMULATION_PLUGIN_WITH_EXAMPLE), not on the
// shipped four-bar, and every check passes there.
TEST(LagrangeBaumgarte, CheckRunsOnTheExampleModelItDeclares) {
  EXPECT_NE(host().example_model().find("cut_joints"), std::string::npos);
  const th::CheckReport r = th::check_library(LAGRANGE_BAUMGARTE_LIBRARY, nullptr);
  bool on_example = false;
  for (const th::Check& c : r.checks) {
    EXPECT_NE(c.verdict, th::Check::Verdict::failed) << c.what << ": " << c.detail;
    on_example = on_example || (c.verdict == th::Check::Verdict::note &&
                                c.detail.rfind("the example model of formulation "
                                               "'lagrange-baumgarte'",
                                               0) == 0);
  }
  EXPECT_TRUE(on_example);
  EXPECT_TRUE(r.passed());
}

TEST(LagrangeBaumgarte, PassesEveryContractCheck) {
  const th::CheckReport r = host().check(free_fourbar("{name: lagrange-baumgarte}"));
  for (const th::Check& c : r.checks)
    EXPECT_NE(c.verdict, th::Check::Verdict::failed) << c.what << ": " << c.detail;
  EXPECT_TRUE(r.passed());
  EXPECT_GE(r.checks.size(), 5u);  // the model, cycles, bad options, tangent, reruns
}

}  // namespace
