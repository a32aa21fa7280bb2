// The shared Newton step: quadratic convergence, honest failures.
#include <gtest/gtest.h>

#include <cmath>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const char* kPendulum = R"(
units: {length: m, mass: kg, time: s, angle: deg}
name: pendulum
bodies:
  - name: rod
    parent: ground
    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 1.0
    shape: {type: beam, length: 1.0}
    z0: 30
formulation: open-loop
solver: {dt: 0.02, t_end: 1, max_iterations: 12, tol_position: 1e-14}
)";

TEST(TrapezoidalStep, NewtonConvergesQuadraticallyOnAPendulum) {
  const ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  sim.step();
  const auto& inc = sim.last_step().increment_norms;  // in units of tol = 1e-14
  ASSERT_GE(inc.size(), 3u);
  // Each increment is at most C times the square of the previous one while
  // both are above round-off (measured: 1.9e-6 rad, then 1.1e-14 rad).
  int quadratic_pairs = 0;
  for (size_t h = 0; h + 1 < inc.size(); ++h) {
    const double e0 = inc[h] * 1e-14, e1 = inc[h + 1] * 1e-14;
    if (e0 < 1e-9 || e1 < 1e-15) continue;
    EXPECT_LE(e1, 10.0 * e0 * e0) << "iteration " << h;
    ++quadratic_pairs;
  }
  EXPECT_GE(quadratic_pairs, 1);
  EXPECT_LE(inc.back(), 1.0);
}

TEST(TrapezoidalStep, AFailedStepNamesItsTimeStepAndUnknownAndKeepsTheLastState) {
  ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  file.solver.max_iterations = 1;
  file.solver.tol_position = 1e-300;
  Simulation sim(file, test::build_plugins());
  sim.start();
  const double z0 = sim.z()[0];
  try {
    sim.step();
    FAIL() << "expected SimulationError";
  } catch (const SimulationError& e) {
    EXPECT_DOUBLE_EQ(e.time(), 0.02);
    EXPECT_EQ(e.step(), 1);
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("t = 0.02 s, step 1: Newton did not converge in 1 iterations", 0), 0u)
        << msg;
    EXPECT_NE(msg.find("unknown 'z1' of formulation 'open-loop'"), std::string::npos) << msg;
  }
  EXPECT_EQ(sim.time(), 0.0);
  EXPECT_EQ(sim.step_index(), 0);
  EXPECT_EQ(sim.z()[0], z0);
}

TEST(TrapezoidalStep, TheTangentIsAnalysedOnceWithADenseMechanicalBlock) {
  const ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  Simulation sim(file, test::build_plugins());
  EXPECT_EQ(sim.num_unknowns(), 1);
  EXPECT_EQ(sim.tangent_nonzeros(), 1);
}

TEST(TrapezoidalStep, StartsAtRestWithTheStaticAccelerationOfAPendulum) {
  const ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  // Rod about its end: I = m L^2 / 3, torque -m g L/2 cos(z).
  const double expected = -9.81 * 0.5 * std::cos(M_PI / 6.0) / (1.0 / 3.0);
  EXPECT_NEAR(sim.zdd()[0], expected, 1e-12);
  EXPECT_EQ(sim.kinetic_energy(), 0.0);
  EXPECT_EQ(sim.drift(), 0.0);
}

}  // namespace
}  // namespace mh
