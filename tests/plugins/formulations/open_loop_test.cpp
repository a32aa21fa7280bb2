// The open-loop formulation: energy conservation of the trapezoidal rule and
// its second order of accuracy; on a tree, equations of motion computed on
// the mechanical block's pattern alone (sparsity.h) that are the dense ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

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

// A tree of bounded depth: a base beam and `arms` arms of two beams on its
// tip, 1 + 2 arms bodies, so that the mechanical pattern (the ancestor pairs)
// leaves most of M' out.
std::string tree_model(int arms) {
  auto beam = [](const std::string& name, const std::string& parent, double at, double z0) {
    return "  - {name: " + name + ", parent: " + parent + ", joint: {type: revolute, at: [" +
           std::to_string(at) + ", 0, 0], axis: [0, 0, 1]}, mass: 1, shape: {type: beam, " +
           "length: 0.5}, z0: " + std::to_string(z0) + "}\n";
  };
  std::string text = "units: {length: m, mass: kg, time: s, angle: deg}\nbodies:\n";
  text += beam("base", "ground", 0.0, 10.0);
  for (int a = 0; a < arms; ++a) {
    const std::string id = std::to_string(a);
    text += beam("a" + id, "base", 0.5, 360.0 * a / arms + 5.0);
    text += beam("c" + id, "a" + id, 0.5, 20.0);
  }
  return text + "formulation: open-loop\nsolver: {dt: 0.001, t_end: 1}\n";
}

// The formulation forms M' zdd on the pattern only; the state it accepts
// solves the dense M' zdd = Q' (the host's M' and Q' there, every entry) to
// Newton's tolerance, while the tree has swung well away from its start.
TEST(OpenLoop, ATreesAcceptedStateSolvesTheDenseEquationsOfMotion) {
  const ModelFile file = parse_model_text(tree_model(12), "tree.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  const Eigen::VectorXd z0 = sim.z();
  for (int k = 0; k < 300; ++k) sim.step();
  const Eigen::VectorXd zdd = sim.zdd();
  const Eigen::VectorXd r = sim.dynamics_residual(sim.z(), sim.zd(), zdd);
  const Eigen::VectorXd Mzdd = r + sim.dynamics_residual(sim.z(), sim.zd(), 0.0 * zdd) * -1.0;
  EXPECT_GT((sim.z() - z0).cwiseAbs().maxCoeff(), 0.05) << "the tree did not move";
  EXPECT_GT(Mzdd.cwiseAbs().maxCoeff(), 1.0);  // M' zdd of the swinging arms, N m
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-6 * Mzdd.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace mh
