// The shared Newton step: quadratic convergence, honest failures.
#include <gtest/gtest.h>

#include <cmath>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run.hpp"
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
  // A long step (0.1 s): with the analytic tangent a 0.02 s step converges in
  // two iterations, the second already at round-off, too few to see the order.
  ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  file.solver.dt = 0.1;
  file.solver.newton = NewtonKind::full;  // a tangent at every iterate
  Simulation sim(file, test::build_plugins());
  sim.start();
  sim.step();
  const auto& inc = sim.last_step().increment_norms;  // in units of tol = 1e-14
  ASSERT_GE(inc.size(), 3u);
  // Each increment is at most C times the square of the previous one while
  // both are above round-off.
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

// Per-step Newton (the default) factors the tangent once, at the prediction:
// its first increment is full Newton's to the bit, and the later ones are
// chord steps on that tangent, contracting linearly at a rate of the order of
// the first increment (far below the 1/2 at which it would refactor).
TEST(TrapezoidalStep, PerStepNewtonTakesFullNewtonsFirstIncrementThenContractsOnOneTangent) {
  ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  file.solver.dt = 0.1;
  file.solver.newton = NewtonKind::full;
  Simulation full(file, test::build_plugins());
  file.solver.newton = NewtonKind::per_step;
  Simulation per_step(file, test::build_plugins());
  full.start();
  per_step.start();
  full.step();
  per_step.step();
  const auto& f = full.last_step().increment_norms;
  const auto& p = per_step.last_step().increment_norms;
  ASSERT_GE(p.size(), 3u);
  EXPECT_EQ(p[0], f[0]);
  EXPECT_EQ(per_step.last_step().tangents, 1);
  EXPECT_EQ(full.last_step().tangents, full.last_step().iterations);
  for (size_t h = 0; h + 1 < p.size(); ++h) {
    if (p[h + 1] * 1e-14 < 1e-15) break;  // round-off
    const double rate = p[h + 1] / p[h];
    ::testing::Test::RecordProperty("rate" + std::to_string(h), test::scientific(rate));
    EXPECT_LT(rate, 0.05) << "iteration " << h;
  }
  // The second increment is a chord step from full Newton's first iterate on a
  // tangent |dx_1| away from it: full Newton's second to within that distance
  // (here 1e-3 rad). The third is where the kinds part: full Newton's is the
  // square of the second (round-off), the chord's a fixed fraction of it.
  ASSERT_GE(f.size(), 3u);
  EXPECT_NEAR(p[1], f[1], 1e-2 * f[1]);
  EXPECT_GT(p[2], 100.0 * f[2]);
  EXPECT_LE(p.back(), 1.0);
  // Both solve the same step to the same tolerance (1e-14 rad).
  EXPECT_NEAR(per_step.z()[0], full.z()[0], 1e-13);
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

namespace mh {
namespace {

// solver.max_step_halvings: a step whose Newton iteration fails is retried as
// two halves. With two Newton iterations allowed, the four-bar's steps at the
// valve's opening (which need three with full Newton) fail; halving them lets
// the run through, and the result stays within the trapezoidal rule's error of
// the normal run.
TEST(TimeStep, AFailedStepIsRetriedAsTwoHalvesUpToTheModelsLimit) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.t_end = 1.5;  // the valve opens at 1 s
  file.solver.newton = NewtonKind::full;
  Simulation reference(file, test::build_plugins());
  const RunSummary ref = run(reference, nullptr);
  ASSERT_FALSE(ref.failed) << ref.failure;
  ASSERT_EQ(ref.max_iterations, 3);  // some steps need three

  file.solver.max_iterations = 2;
  Simulation strict(file, test::build_plugins());
  const RunSummary failed = run(strict, nullptr);
  ASSERT_TRUE(failed.failed);
  EXPECT_NE(failed.failure.find("Newton did not converge in 2 iterations"), std::string::npos)
      << failed.failure;

  file.solver.max_step_halvings = 4;
  Simulation halving(file, test::build_plugins());
  const RunSummary s = run(halving, nullptr);
  ASSERT_FALSE(s.failed) << s.failure;
  EXPECT_EQ(s.steps, ref.steps);
  EXPECT_GT(s.retries, 0);
  EXPECT_LE(s.max_iterations, 2 * (1 + 2 + 4 + 8 + 16));  // every attempt's iterations count
  const double dz = (halving.z() - reference.z()).lpNorm<Eigen::Infinity>();
  ::testing::Test::RecordProperty("retries", std::to_string(s.retries));
  ::testing::Test::RecordProperty("dz", test::scientific(dz));
  EXPECT_LT(dz, 1e-5);  // the 1 ms run's own error is ~6e-6 rad (docs/results.md)
  EXPECT_LT(std::abs(halving.drift()), 1e-3 * std::abs(halving.work()) + 1e-6);
}

// When every halving fails too, the message says how many were tried.
TEST(TimeStep, AStepThatFailsAtEveryHalvingSaysHowManyWereTried) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.t_end = 1.5;
  file.solver.max_iterations = 1;  // one Newton iteration never meets the tolerance
  file.solver.max_step_halvings = 2;
  Simulation sim(file, test::build_plugins());
  const RunSummary s = run(sim, nullptr);
  ASSERT_TRUE(s.failed);
  EXPECT_NE(s.failure.find("halvings of the step, the most the model allows: "
                           "solver.max_step_halvings = 2)"),
            std::string::npos)
      << s.failure;
}

}  // namespace
}  // namespace mh
