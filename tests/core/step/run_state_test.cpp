// Snapshots of a run (run_state.hpp): a restored run repeats the steps that
// followed the save, in the run it was saved from and in a fresh one; what
// cannot be saved or restored is refused with the reason.
#include "monohydra/core/run_state.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "run_trace.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::largest_difference;
using Trace = test::RunTrace;

Trace steps(Simulation& sim, int count) {
  return test::trace_steps(sim, count);
}

struct Case {
  const char* model;
  const char* formulation;
  const char* integrator;
  int before, after;  // steps before the save and after it
};

std::ostream& operator<<(std::ostream& os, const Case& c) {
  return os << c.model << ", " << c.formulation << ", " << c.integrator;
}

class RestoredRun : public ::testing::TestWithParam<Case> {};

// The four-bar's valve opens at t = 1 s (a time event) and the excavator's
// double-step re-partitions: both lie inside the steps after the save.
TEST_P(RestoredRun, RepeatsTheStepsAfterTheSaveToTheLastBitHereAndInAFreshRun) {
  const Case& c = GetParam();
  const ModelFile file = load_model_file(test::source_path(std::string("models/") + c.model));
  RunChoices choices;
  choices.formulation = c.formulation;
  choices.integrator = c.integrator;
  Simulation run(file, test::build_plugins(), choices);
  run.start();
  for (int k = 0; k < c.before; ++k) run.step();
  const RunState saved = run.save_state();
  const Trace first = steps(run, c.after);

  run.restore_state(saved);
  EXPECT_EQ(run.time(), saved.data.accepted.t);
  const Trace again = steps(run, c.after);
  EXPECT_EQ(largest_difference(first, again), 0.0) << "restored into the run it came from";

  Simulation fresh(file, test::build_plugins(), choices);  // never started: restore starts it
  const RunState copy = saved;                             // a snapshot is a value
  fresh.restore_state(copy);
  const Trace elsewhere = steps(fresh, c.after);
  EXPECT_EQ(largest_difference(first, elsewhere), 0.0) << "restored into a fresh run";
}

INSTANTIATE_TEST_SUITE_P(
    CaseStudies, RestoredRun,
    ::testing::Values(Case{"fourbar.yaml", "double-step", "trapezoidal", 990, 40},
                      Case{"fourbar.yaml", "penalty", "trapezoidal", 990, 40},
                      Case{"fourbar.yaml", "double-step", "bdf2", 990, 40},
                      Case{"fourbar.yaml", "penalty", "generalized-alpha", 990, 40},
                      Case{"quickreturn.yaml", "double-step", "trapezoidal", 300, 200},
                      Case{"quickreturn.yaml", "penalty", "bdf2", 300, 200},
                      Case{"double-pendulum.yaml", "open-loop", "trapezoidal", 50, 50}));

// Modified Newton keeps a factorization from step to step: the snapshot
// carries it (as the values it was made from), so the restored run iterates
// on the same factors.
TEST(RunState, ModifiedNewtonRestoredIteratesOnTheKeptFactorizationToTheLastBit) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.newton = NewtonKind::modified;
  RunChoices choices;
  choices.formulation = "penalty";
  Simulation run(file, test::build_plugins(), choices);
  run.start();
  for (int k = 0; k < 1005; ++k) run.step();  // the valve opened at 1 s
  const RunState saved = run.save_state();
  ASSERT_FALSE(saved.kept_tangent.empty());
  const Trace first = steps(run, 60);
  Simulation fresh(file, test::build_plugins(), choices);
  fresh.restore_state(saved);
  EXPECT_EQ(largest_difference(first, steps(fresh, 60)), 0.0);
  // A full-Newton run of the same model is another run.
  const ModelFile full_newton = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation full(full_newton, test::build_plugins(), choices);
  EXPECT_THROW(full.restore_state(saved), RunStateError);
}

// Full and per-step Newton keep no factorization between steps: a state of
// either restores into a run of the other, which goes on in its own kind (a
// tangent at every iteration, or one per step).
TEST(RunState, FullAndPerStepNewtonStatesRestoreIntoEachOthersRunsWhichKeepTheirOwnKind) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.newton = NewtonKind::per_step;
  Simulation per_step(file, test::build_plugins(), "penalty");
  file.solver.newton = NewtonKind::full;
  Simulation full(file, test::build_plugins(), "penalty");
  per_step.start();
  full.start();
  for (int k = 0; k < 1005; ++k) {  // the valve opened at 1 s: steps of two iterations or more
    per_step.step();
    full.step();
  }
  const RunState from_per_step = per_step.save_state();
  const RunState from_full = full.save_state();
  full.restore_state(from_per_step);
  per_step.restore_state(from_full);
  int full_iterations = 0, per_step_iterations = 0;
  for (int k = 0; k < 30; ++k) {
    full.step();
    per_step.step();
    EXPECT_EQ(full.last_step().tangents, full.last_step().iterations) << k;
    EXPECT_EQ(per_step.last_step().tangents, 1) << k;
    full_iterations += full.last_step().iterations;
    per_step_iterations += per_step.last_step().iterations;
  }
  EXPECT_GT(full_iterations, 30);  // so the kinds differ on these steps
  EXPECT_GT(per_step_iterations, 30);
}

TEST(RunState, AStateOfAnotherFormulationIsRefusedNamingBoth) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation a(file, test::build_plugins(), "double-step");
  Simulation b(file, test::build_plugins(), "penalty");
  a.start();
  b.start();
  a.step();
  const RunState saved = a.save_state();
  try {
    b.restore_state(saved);
    FAIL() << "a double-step state restored into a penalty run";
  } catch (const RunStateError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("not one of this run"), std::string::npos) << what;
    EXPECT_NE(what.find("'double-step'"), std::string::npos) << what;
    EXPECT_NE(what.find("'penalty'"), std::string::npos) << what;
  }
  b.step();  // b goes on as it was
  EXPECT_EQ(b.step_index(), 1);
}

TEST(RunState, BytesAnInstanceRefusesLeaveTheWholeRunAsItWas) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation run(file, test::build_plugins(), "double-step");
  Simulation twin(file, test::build_plugins(), "double-step");
  run.start();
  twin.start();
  for (int k = 0; k < 10; ++k) {
    run.step();
    twin.step();
  }
  RunState garbled = run.save_state();
  ASSERT_FALSE(garbled.part_sizes.empty());
  // The formulation's part first: 0xff bytes make its partition's indices -1.
  std::fill_n(garbled.part_bytes.begin(), garbled.part_sizes[0], static_cast<unsigned char>(0xff));
  garbled.data.accepted.z.setConstant(1e3);  // the host's part: not taken either
  try {
    run.restore_state(garbled);
    FAIL() << "garbled bytes restored";
  } catch (const RunStateError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("load_state"), std::string::npos) << what;
    EXPECT_NE(what.find("partition"), std::string::npos) << what;
  }
  EXPECT_EQ(largest_difference(steps(run, 30), steps(twin, 30)), 0.0);
}

TEST(RunState, ARunWhoseFormulationCannotSaveIsRefusedNamingIt) {
  const ModelFile file = load_model_file(test::source_path("models/double-pendulum.yaml"));
  const PluginRegistry& plugins = test::build_plugins_with(
      std::string(mh::test::paths::faulty_plugin_dir) + "/crashing_formulation.so");
  Simulation run(file, plugins, "crashing-formulation");
  EXPECT_THROW((void)run.save_state(), RunStateError);  // not started
  run.start();
  run.step();
  try {
    (void)run.save_state();
    FAIL() << "saved a run whose formulation has no state extension";
  } catch (const RunStateError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("'crashing-formulation'"), std::string::npos) << what;
    EXPECT_NE(what.find("monohydra.state/3"), std::string::npos) << what;
  }
  run.step();  // the run goes on
  EXPECT_EQ(run.step_index(), 2);
}

}  // namespace
}  // namespace mh
