// The overrides every command takes the same way (step_overrides.hpp): what
// they parse into, what they replace in a model's settings, and the same
// refusal from run, compare and sweep.
#include "step_overrides.hpp"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "subcommand_parser.hpp"
#include "test_support.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;

TEST(StepOverrides, TheOptionsParseIntoTheirValuesAndReplaceOnlyWhatWasGiven) {
  const auto holder = mh::cli::subcommand_app("run", "test");
  const mh::cli::StepOverrideOptions options(*holder, true, true);
  ASSERT_FALSE(mh::cli::parse_subcommand(
                   *holder, {"--dt", "2e-4", "--max-steps", "5e5", "--explicit-stability", "off"})
                   .has_value());
  mh::cli::StepOverrides o;
  ASSERT_TRUE(options.read(o));
  EXPECT_EQ(o.dt, 2e-4);
  EXPECT_FALSE(o.t_end.has_value());
  EXPECT_EQ(o.limits.max_steps, 5e5);
  EXPECT_EQ(o.limits.max_output_bytes, mh::RunLimits{}.max_output_bytes);
  mh::SolverSettings file;
  file.dt = 1e-3;
  file.t_end = 7.0;
  const mh::SolverSettings s = o.applied_to(file);
  EXPECT_EQ(s.dt, 2e-4);
  EXPECT_EQ(s.t_end, 7.0);
  EXPECT_EQ(s.explicit_stability, mh::ExplicitStabilityPolicy::off);
  EXPECT_TRUE(o.origins().dt_flag);
  EXPECT_FALSE(o.origins().t_end_flag);
}

TEST(StepOverrides, ANonNumberIsRefusedAlikeByRunCompareAndSweep) {
  const std::string model = mh::test::source_path("models/double-pendulum.yaml");
  for (const std::string& command : {"run " + model, "validate " + model, "compare " + model,
                                     std::string("sweep study.yaml --out d")}) {
    const CliResult r = run_cli(command + " --dt soon");
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("monohydra: --dt expects a number, got 'soon'"), std::string::npos)
        << command << "\n"
        << r.output;
  }
}

TEST(StepOverrides, RunAndCompareRefuseANegativeStepWithTheSameMessage) {
  const std::string model = mh::test::source_path("models/double-pendulum.yaml");
  std::vector<std::string> messages;
  for (const std::string& command : {"run " + model, "compare " + model}) {
    const CliResult r = run_cli(command + " --dt -1");
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    const size_t at = r.output.find("--dt: expected a time step");
    ASSERT_NE(at, std::string::npos) << command << "\n" << r.output;
    messages.push_back(r.output.substr(at, r.output.find('\n', at) - at));
  }
  EXPECT_EQ(messages[0], messages[1]);
}

}  // namespace
