// The subcommands on CLI11: each answers --help with its usage and options
// (exit 0), and an unknown option or a missing value is an error (exit 2)
// naming it.
#include "subcommand_parser.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;

TEST(SubcommandParser, EverySubcommandOnCli11AnswersHelpWithItsOptions) {
  for (const auto& [command, option] :
       std::vector<std::pair<std::string, std::string>>{{"run", "--output-interval"},
                                                        {"validate", "--newton-cap"},
                                                        {"compare", "--formulations"},
                                                        {"plugins", "--model"},
                                                        {"check", "PLUGIN.so"}}) {
    const CliResult r = run_cli(command + " --help");
    EXPECT_EQ(r.code, 0) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("Usage: monohydra " + command), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(option), std::string::npos) << command << "\n" << r.output;
  }
}

TEST(SubcommandParser, AnUnknownOptionIsNamedAndExitsTwo) {
  const auto holder = mh::cli::subcommand_app("run", "test");
  CLI::App& app = *holder;
  std::string dt;
  app.add_option("--dt", dt, "time step");
  testing::internal::CaptureStderr();
  const auto code = mh::cli::parse_subcommand(app, {"--dt", "0.1", "--frobnicate"});
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  EXPECT_NE(err.find("unknown option '--frobnicate'"), std::string::npos) << err;
}

TEST(SubcommandParser, AMissingValueIsAnErrorAndAGivenOneIsKeptAsText) {
  {
    const auto app = mh::cli::subcommand_app("run", "test");
    std::string dt;
    app->add_option("--dt", dt, "time step");
    testing::internal::CaptureStderr();
    const auto code = mh::cli::parse_subcommand(*app, {"--dt"});
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_TRUE(code.has_value());
    EXPECT_EQ(*code, 2);
    EXPECT_NE(err.find("--dt"), std::string::npos) << err;
  }
  const auto app = mh::cli::subcommand_app("run", "test");
  std::string dt;
  app->add_option("--dt", dt, "time step");
  EXPECT_FALSE(mh::cli::parse_subcommand(*app, {"--dt", "-1e-3"}).has_value());
  EXPECT_EQ(dt, "-1e-3");  // a negative number is a value, checked by the command
}

}  // namespace
