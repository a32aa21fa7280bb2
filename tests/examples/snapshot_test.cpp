// The examples offer their state (MH_EXT_STATE) as a plugin author would:
// a run with the explicit rk4 or with the lagrange-baumgarte formulation,
// saved and restored into a fresh run, repeats its steps to the last bit.
#include <gtest/gtest.h>

#include <string>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "run_trace.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

void expect_restored_run_repeats(const PluginRegistry& plugins, const RunChoices& choices,
                                 int before, int after) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation run(file, plugins, choices);
  run.start();
  for (int k = 0; k < before; ++k) run.step();
  const RunState saved = run.save_state();
  const test::RunTrace first = test::trace_steps(run, after);
  Simulation fresh(file, plugins, choices);
  fresh.restore_state(saved);
  EXPECT_EQ(test::largest_difference(first, test::trace_steps(fresh, after)), 0.0);
}

TEST(ExampleSnapshots, AnExplicitRk4RunRestoredRepeatsItsStepsToTheLastBit) {
  // 0.1 ms: rk4 is stable on the four-bar there (rk4_stability_test.cpp).
  expect_restored_run_repeats(
      test::build_plugins_with(std::string(mh::test::paths::examples_dir) + "/rk4/rk4.so"),
      RunChoices{"double-step", "rk4", 1e-4, 1.02}, 9950, 150);
}

TEST(ExampleSnapshots, ALagrangeBaumgarteRunRestoredRepeatsItsStepsToTheLastBit) {
  expect_restored_run_repeats(test::build_plugins_with(std::string(mh::test::paths::examples_dir) +
                                                       "/lagrange-baumgarte/lagrange-baumgarte.so"),
                              RunChoices{"lagrange-baumgarte", "", std::nullopt, 1.05}, 990, 50);
}

}  // namespace
}  // namespace mh
