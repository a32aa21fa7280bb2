// The open-loop formulation: energy conservation of the trapezoidal rule and
// its second order of accuracy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

TEST(OpenLoop, DoublePendulumConservesEnergyOverTenSecondsAtOneMillisecond) {
  const ModelFile file = load_model_file(test::source_path("models/double-pendulum.yaml"));
  Simulation sim(file, test::build_plugins());
  ASSERT_DOUBLE_EQ(sim.settings().dt, 1e-3);
  ASSERT_DOUBLE_EQ(sim.settings().t_end, 10.0);
  const RunSummary s = run(sim, nullptr);
  ASSERT_FALSE(s.failed) << s.failure;
  EXPECT_EQ(s.steps, 10000);
  // Both links start horizontal and can fall through 19.6 J of potential
  // energy; the peak drift of KE + PE stays below 4e-3 J (2e-4 of it; measured
  // 2.85e-3 J), and it is O(dt^2): see the next test.
  EXPECT_LT(s.max_abs_drift, 4e-3);
  EXPECT_GT(s.max_abs_drift, 0.0);  // it is measured, not identically zero
  EXPECT_EQ(sim.work(), 0.0);       // no subsystems
}

// z(t = 0.5 s) of the double pendulum at time step dt.
Eigen::VectorXd state_at_half_second(double dt) {
  ModelFile file = load_model_file(test::source_path("models/double-pendulum.yaml"));
  file.solver.dt = dt;
  file.solver.t_end = 0.5;
  Simulation sim(file, test::build_plugins());
  const RunSummary s = run(sim, nullptr);
  EXPECT_FALSE(s.failed) << s.failure;
  return sim.z();
}

TEST(OpenLoop, EnergyDriftShrinksFourfoldWhenTheStepHalves) {
  double drift[2] = {0.0, 0.0};
  for (int i = 0; i < 2; ++i) {
    ModelFile file = load_model_file(test::source_path("models/double-pendulum.yaml"));
    file.solver.dt = i == 0 ? 2e-3 : 1e-3;
    file.solver.t_end = 3.0;
    Simulation sim(file, test::build_plugins());
    const RunSummary s = run(sim, nullptr);
    ASSERT_FALSE(s.failed) << s.failure;
    drift[i] = s.max_abs_drift;
  }
  EXPECT_NEAR(drift[0] / drift[1], 4.0, 0.6);
}

TEST(OpenLoop, TrapezoidalRuleConvergesAtSecondOrder) {
  const Eigen::VectorXd z4 = state_at_half_second(4e-3);
  const Eigen::VectorXd z2 = state_at_half_second(2e-3);
  const Eigen::VectorXd z1 = state_at_half_second(1e-3);
  const double ratio = (z4 - z2).norm() / (z2 - z1).norm();
  EXPECT_NEAR(ratio, 4.0, 0.4);  // halving dt quarters the error
}

}  // namespace
}  // namespace mh
