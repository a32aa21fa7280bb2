// The run's state set from outside (core/src/analysis/state_vector.cpp):
// what it reads back, that the closed loops stay closed, that the run goes
// on from it as from a state it reached itself, and its refusals.
#include "monohydra/core/state_vector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const ModelFile& fourbar() {
  static const ModelFile file = [] {
    ModelFile f = load_model_file(test::source_path("models/fourbar.yaml"));
    f.solver.t_end = 3.0;
    return f;
  }();
  return file;
}

void run_to(Simulation& sim, double t) {
  while (sim.time() < t - 1e-12) sim.step();
}

TEST(StateVector, AStateSetIsTheStateReadBackWithTheLoopsClosed) {
  Simulation sim(fourbar(), test::build_plugins(), "double-step");
  sim.start();
  run_to(sim, 1.5);  // the valve open, the mechanism moving
  Eigen::VectorXd x = state_values(sim);
  ASSERT_EQ(x.size(), 6);  // z3, z3_dot, p1, p2, p3, U
  x[0] += 1e-3;            // rad
  x[1] += 1e-2;            // rad/s
  x[3] += 1e5;             // Pa
  set_state_values(sim, x);
  const Eigen::VectorXd back = state_values(sim);
  EXPECT_LT((back - x).cwiseAbs().cwiseQuotient(x.cwiseAbs().cwiseMax(1.0)).maxCoeff(), 1e-12);
  // The dependent coordinates moved with z3: the loop stays closed.
  EXPECT_LT(sim.phi_norm(), 1e-9);
  sim.step();
  EXPECT_LT(sim.phi_norm(), 1e-9);
}

TEST(StateVector, ARunSetToAnothersStateGoesOnAsThatRun) {
  // b is knocked off a's path at 1 s, and set back to a's state at 1.5 s:
  // from there it goes on as a does, to what the integrator's restart
  // changes (the trapezoidal rule's history, from the consistent rates).
  Simulation a(fourbar(), test::build_plugins(), "double-step");
  Simulation b(fourbar(), test::build_plugins(), "double-step");
  a.start();
  b.start();
  run_to(b, 1.0);
  Eigen::VectorXd knocked = state_values(b);
  knocked[1] += 0.05;  // rad/s
  knocked[2] -= 3e5;   // Pa
  set_state_values(b, knocked);
  run_to(a, 1.5);
  run_to(b, 1.5);
  const Eigen::VectorXd apart = state_values(b) - state_values(a);
  set_state_values(b, state_values(a));
  for (int k = 0; k < 500; ++k) {
    a.step();
    b.step();
  }
  const Eigen::VectorXd after = state_values(b) - state_values(a);
  for (Eigen::Index i = 0; i < 5; ++i)
    EXPECT_LT(std::abs(after[i]), 1e-6 * std::abs(apart[i]))
        << i << ": " << apart[i] << " -> " << after[i];
}

TEST(StateVector, RefusesAWrongSizeANonFiniteValueAndARunNotStarted) {
  Simulation sim(fourbar(), test::build_plugins(), "double-step");
  EXPECT_THROW(set_state_values(sim, Eigen::VectorXd::Zero(6)), SimulationError);
  sim.start();
  const Eigen::VectorXd before = state_values(sim);
  EXPECT_THROW(set_state_values(sim, Eigen::VectorXd::Zero(5)), std::invalid_argument);
  Eigen::VectorXd bad = before;
  bad[2] = NAN;
  try {
    set_state_values(sim, bad);
    FAIL() << "NaN accepted";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("p1"), std::string::npos) << err.what();
  }
  EXPECT_EQ(state_values(sim), before);
}

TEST(StateVector, PenaltysCoordinatesMovedStayOnTheConstraints) {
  Simulation sim(fourbar(), test::build_plugins(), "penalty");
  sim.start();
  run_to(sim, 1.5);
  const std::vector<LinearVariable> names = state_variables(sim);
  Eigen::VectorXd x = state_values(sim);
  // Every coordinate moved by 1e-4 rad: across the constraints too.
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i].unit == "rad") x[static_cast<Eigen::Index>(i)] += 1e-4;
  set_state_values(sim, x);
  // Moved within the tangent space: the constraints violated to second
  // order in the move only (1e-8 against the 1e-4 a move across them makes).
  EXPECT_LT(sim.phi_norm(), 1e-7);
}

}  // namespace
}  // namespace mh
