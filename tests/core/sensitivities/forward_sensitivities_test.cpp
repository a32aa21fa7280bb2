// Forward sensitivities (core/src/sensitivities/forward_sensitivities.cpp)
// against an independent computation: central differences of whole runs of
// the model with the parameter changed, Newton converged to round-off, on
// the hydraulic four-bar with both formulations, through the valve's
// opening and closing (time events): a body's mass (which moves its
// inertia too), gravity, an initial coordinate, and the components' options
// the issue of identification names (a volume's bulk modulus, the valve's flow coefficient and time
// constant, the cylinder's piston diameter, the supply pressure), changed in
// place by their instances (the pressure, a number read as a signal, by the
// engine) against whole runs whose instances read the changed value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/sensitivities/parameter_directions.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A shipped model with Newton converged to round-off: full Newton, a tight tolerance.
ModelFile converged(const std::string& name, double t_end) {
  ModelFile file = load_model_file(test::source_path("models/" + name));
  file.solver.newton = NewtonKind::full;
  // 1e-11 left penalty's multipliers short of Phi = 0 by enough to move the
  // volume's small effect on the coordinates in whole runs by 1.4e-4.
  file.solver.tol_position = 1e-13;
  file.solver.t_end = t_end;
  return file;
}
ModelFile fourbar(double t_end) {
  return converged("fourbar.yaml", t_end);
}

ParameterDirection gravity_y() {
  ParameterDirection p;
  p.path = "gravity/1";
  p.value = -9.81;
  p.gravity = Eigen::Vector3d(0, 1, 0);
  return p;
}
// A body's initial coordinate (rad or m, as the parsed model holds it):
// start() differenced with the loops closed again around it.
ParameterDirection initial_coordinate(const ModelFile& file, size_t body) {
  const Body& b = file.model.bodies[body];
  ParameterDirection p;
  p.path = "bodies/" + b.name + "/z0";
  p.value = b.z0;
  p.initial.push_back({static_cast<int>(body), 1.0, 0.0});
  return p;
}
// The model moved by `amount` along p: a component's option as the file
// would write it, read by a new instance at its setup.
ModelFile moved(ModelFile file, const ParameterDirection& p, double amount) {
  for (SubsystemSpec& s : file.subsystems)
    if (s.name == p.subsystem) s.options.at(p.key).number += amount * p.option;
  for (const auto& c : p.bodies) {
    Body& b = file.model.bodies[static_cast<size_t>(c.body)];
    b.mass += amount * c.mass;
    b.com_B += amount * c.com;
    b.inertia_B += amount * c.inertia;
  }
  for (const auto& c : p.initial) {
    Body& b = file.model.bodies[static_cast<size_t>(c.coordinate)];
    b.z0 += amount * c.z0;
    b.zd0 += amount * c.zd0;
  }
  file.model.gravity += amount * p.gravity;
  return file;
}

// A run's samples: coordinates and states at every `every` steps.
struct Samples {
  std::vector<Eigen::VectorXd> values;       // [z; y]
  std::vector<Eigen::MatrixXd> derivatives;  // [dz; dy] when tracked
};

Samples run(const ModelFile& file, const std::string& formulation, long every,
            const std::vector<ParameterDirection>& params = {}) {
  Simulation sim(file, test::build_plugins(), formulation);
  if (!params.empty()) sim.track_sensitivities(params);
  sim.start();
  Samples out;
  const long steps = std::lround(file.solver.t_end / file.solver.dt);
  for (long k = 0; k <= steps; ++k) {
    if (k > 0) sim.step();
    if (k % every != 0) continue;
    Eigen::VectorXd v(sim.z().size() + sim.states().size());
    v << sim.z(), sim.states();
    out.values.push_back(v);
    if (!params.empty()) {
      Eigen::MatrixXd d(v.size(), static_cast<Eigen::Index>(params.size()));
      d << sim.coordinate_sensitivities(), sim.state_sensitivities();
      out.derivatives.push_back(d);
    }
  }
  return out;
}

// `reference_steps[j]`: parameter j's whole runs differenced at that part
// of its value (default 1e-5), where a response too curved or too small
// for 1e-5 needs another (the callers say why).
void expect_columns_match_whole_runs(const ModelFile& file, const std::string& formulation,
                                     const std::vector<ParameterDirection>& params,
                                     const std::vector<Eigen::Index>& at_rest = {},
                                     const std::vector<double>& reference_steps = {}) {
  const long every = 50;
  const Samples tracked = run(file, formulation, every, params);
  for (size_t j = 0; j < params.size(); ++j) {
    // Central differences of whole runs, at 1e-5 of the value (of 1 where it is 0).
    const double relative = j < reference_steps.size() ? reference_steps[j] : 1e-5;
    const double delta = relative * (params[j].value != 0.0 ? std::abs(params[j].value) : 1.0);
    const Samples plus = run(moved(file, params[j], delta), formulation, every);
    const Samples minus = run(moved(file, params[j], -delta), formulation, every);
    ASSERT_EQ(plus.values.size(), tracked.values.size());
    const Eigen::Index rows = tracked.values[0].size();
    // Each row's largest sensitivity over the run: the scale of its error.
    Eigen::VectorXd largest = Eigen::VectorXd::Zero(rows);
    std::vector<Eigen::VectorXd> differenced;
    for (size_t s = 0; s < tracked.values.size(); ++s) {
      differenced.push_back((plus.values[s] - minus.values[s]) / (2.0 * delta));
      largest = largest.cwiseMax(differenced.back().cwiseAbs());
    }
    double worst = 0.0;
    std::string where;
    for (size_t s = 0; s < tracked.values.size(); ++s)
      for (Eigen::Index i = 0; i < rows; ++i) {
        const double scale = largest[i];
        if (scale < 1e-100) continue;  // the row does not depend on p
        if (std::find(at_rest.begin(), at_rest.end(), i) != at_rest.end()) {
          // A coordinate no parameter moves: its column is the differences'
          // round-off, which a 100 % change of p turns into under 1e-6.
          EXPECT_LT(
              std::abs(tracked.derivatives[s](i, static_cast<Eigen::Index>(j)) * params[j].value),
              1e-6)
              << params[j].path << ", row " << i;
          continue;
        }
        const double e =
            std::abs(tracked.derivatives[s](i, static_cast<Eigen::Index>(j)) - differenced[s][i]) /
            scale;
        if (e > worst) {
          worst = e;
          where = "row " + std::to_string(i) +
                  " at t = " + std::to_string(static_cast<double>(s) * every * file.solver.dt);
        }
      }
    EXPECT_LT(worst, 1e-4) << formulation << ", " << params[j].path << ": " << where;
  }
}

// A body's mass, gravity, the valve's time constant and flow coefficient,
// the cylinder's piston diameter, V1's bulk modulus, an initial angle
// (initial_body >= 0) and the supply pressure (a number the pump reads as a
// signal, held by the engine; `supply_pressure`). `flow_reference_step`:
// the flow coefficient's whole runs differenced at that part of its value.
void expect_sensitivities_match_whole_runs(const std::string& model, const std::string& formulation,
                                           double t_end, size_t body, int initial_body,
                                           bool supply_pressure, double flow_reference_step) {
  const ModelFile file = converged(model, t_end);
  std::vector<ParameterDirection> params = {
      test::mass_direction(file.model, body),
      gravity_y(),
      test::option_direction(file, "valve", "time_constant"),
      test::option_direction(file, "cylinder", "piston_diameter"),
      test::option_direction(file, "V1", "bulk_modulus"),
      test::option_direction(file, "valve", "flow_coefficient")};
  std::vector<double> steps(params.size(), 1e-5);
  steps.back() = flow_reference_step;
  if (initial_body >= 0)
    params.push_back(initial_coordinate(file, static_cast<size_t>(initial_body)));
  if (supply_pressure) params.push_back(test::option_direction(file, "pump", "pressure"));
  expect_columns_match_whole_runs(file, formulation, params, {}, steps);
}

// Over 10 s: the valve opens at 1 s and closes at 2.5 s, 5 s and 8 s, and
// the mechanism comes to rest after each closing, its cylinder's friction
// steep in the rate there.
TEST(ForwardSensitivities, DoubleStepFourBarAgreesWithDifferencesOfWholeRuns) {
  expect_sensitivities_match_whole_runs("fourbar.yaml", "double-step", 10.0, 2, 0, true, 1e-5);
}

// Penalty's multipliers converge on Phi = 0 (its accept's projections
// differenced, its step bordered by Phi_z): held fixed instead, the
// columns would be those of a penalty method, far from these. The
// projections round off as their difference step shrinks: at a step of
// 1e-7 of the unknowns this missed by 1.7e-3 after the valve closed at 8 s,
// and the initial angle's column (the four-bar starts at rest, in
// equilibrium: the trapped oil's neutral mode takes the rounding) by 1.9e-4.
TEST(ForwardSensitivities, PenaltyFourBarAgreesWithDifferencesOfWholeRuns) {
  expect_sensitivities_match_whole_runs("fourbar.yaml", "penalty", 10.0, 2, 0, true, 1e-5);
}

// The quick-return over 10 s: five bodies, two sliding cut joints; the
// crank's mass and its initial angle (the crank is held at assembly). Its
// pressures respond to the flow coefficient so unevenly around t = 4.2 s
// that whole runs differenced at 1e-5 of it are off by 6e-4 of the largest
// (at 1e-4 by 1.5e-2): they are differenced at 1e-6, where the columns
// agree with them to 1e-5.
TEST(ForwardSensitivities, DoubleStepQuickReturnAgreesWithDifferencesOfWholeRuns) {
  expect_sensitivities_match_whole_runs("quickreturn.yaml", "double-step", 10.0, 3, 3, true, 1e-6);
}

TEST(ForwardSensitivities, PenaltyQuickReturnAgreesWithDifferencesOfWholeRuns) {
  expect_sensitivities_match_whole_runs("quickreturn.yaml", "penalty", 10.0, 3, 3, true, 1e-6);
}

// The excavator's first 5 s (the arm in, the bucket curling, the boom
// lowered; ten coordinates, three spherical loops, 22 states): the
// bucket's mass (it carries the payload), two valves' flow coefficients, a
// valve's time constant, a cylinder's piston diameter, the boom's initial
// angle (the cylinders' bodies assembled around it) and a line's bulk
// modulus. The slew (z1) is at rest until 6.5 s and none of them moves it:
// its columns are round-off, checked to be negligible instead. V_arm_a's
// bulk modulus moves the left boom cylinder's barrel angle by little:
// whole runs differenced at 1e-5 and 1e-6 of it are rounding there (1.4e-4
// and more of the largest apart), at 1e-4 they agree with the column.
TEST(ForwardSensitivities, DoubleStepExcavatorAgreesWithDifferencesOfWholeRuns) {
  const ModelFile file = converged("excavator.yaml", 5.0);
  expect_columns_match_whole_runs(
      file, "double-step",
      {test::mass_direction(file.model, 3),
       test::option_direction(file, "valve_boom", "flow_coefficient"),
       test::option_direction(file, "valve_arm", "flow_coefficient"),
       test::option_direction(file, "valve_bucket", "time_constant"),
       test::option_direction(file, "arm_cyl", "piston_diameter"), initial_coordinate(file, 1),
       test::option_direction(file, "V_arm_a", "bulk_modulus")},
      {0}, {1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 1e-4});
}

// The two formulations differentiate the same mechanism: their columns agree,
// for a body's and the components' parameters alike (the sanitizers run this
// test, not the 10-s ones: it passes through the same code in both).
TEST(ForwardSensitivities, FormulationsAgreeOnTheFourBarsColumns) {
  const ModelFile file = fourbar(2.0);
  const std::vector<ParameterDirection> params = {
      test::mass_direction(file.model, 2), gravity_y(),
      test::option_direction(file, "valve", "flow_coefficient"),
      test::option_direction(file, "V1", "bulk_modulus"),
      test::option_direction(file, "cylinder", "piston_diameter")};
  const Samples a = run(file, "double-step", 100, params);
  const Samples b = run(file, "penalty", 100, params);
  ASSERT_EQ(a.derivatives.size(), b.derivatives.size());
  const auto k = static_cast<Eigen::Index>(params.size());
  Eigen::ArrayXXd largest = Eigen::ArrayXXd::Zero(a.derivatives[0].rows(), k);
  for (const auto& d : a.derivatives) largest = largest.max(d.array().abs());
  for (size_t s = 0; s < a.derivatives.size(); ++s)
    for (Eigen::Index i = 0; i < largest.rows(); ++i)
      for (Eigen::Index j = 0; j < k; ++j) {
        if (largest(i, j) == 0.0) continue;
        EXPECT_LT(std::abs(a.derivatives[s](i, j) - b.derivatives[s](i, j)), 2e-3 * largest(i, j))
            << "row " << i << ", parameter " << j << ", sample " << s;
      }
}

// Tracking begins at start(): asked for later, it is refused, naming why.
TEST(ForwardSensitivities, RefusedAfterStart) {
  const ModelFile file = fourbar(0.01);
  Simulation sim(file, test::build_plugins(), "double-step");
  sim.start();
  try {
    sim.track_sensitivities({gravity_y()});
    FAIL() << "taken after start()";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("before it"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.num_sensitivities(), 0);
}

// A snapshot holds no columns: a run that tracks them refuses to restore
// one rather than go on with columns of another state.
TEST(ForwardSensitivities, ARunThatTracksThemRefusesToRestoreASnapshot) {
  const ModelFile file = fourbar(0.01);
  Simulation sim(file, test::build_plugins(), "double-step");
  sim.track_sensitivities({gravity_y()});
  sim.start();
  sim.step();
  const RunState state = sim.save_state();
  try {
    sim.restore_state(state);
    FAIL() << "restored";
  } catch (const RunStateError& e) {
    EXPECT_NE(std::string(e.what()).find("tracks sensitivities"), std::string::npos) << e.what();
  }
}

// Tracking changes nothing of the run itself beyond Newton's tolerance.
TEST(ForwardSensitivities, TheRunItselfIsTheRunWithoutThem) {
  const ModelFile file = fourbar(2.0);
  const Samples with = run(file, "penalty", 100, {gravity_y()});
  const Samples without = run(file, "penalty", 100);
  for (size_t s = 0; s < with.values.size(); ++s)
    for (Eigen::Index i = 0; i < with.values[s].size(); ++i)
      EXPECT_NEAR(with.values[s][i], without.values[s][i],
                  1e-9 * std::max(1.0, std::abs(without.values[s][i])))
          << "row " << i << ", sample " << s;
}

}  // namespace
}  // namespace mh
