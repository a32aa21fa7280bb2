// What the subcommands share: numbers as strtod reads them, limits, and the
// clean-up of a CSV a full disk cut mid-row.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

namespace {

TEST(CliSupport, SubnormalAndHugeNumbersAreNumbers) {
  EXPECT_GT(mh::cli::parse_number("--dt", "1e-320").value_or(0.0), 0.0);
  EXPECT_EQ(mh::cli::parse_number("--t-end", "1e400").value_or(0.0), HUGE_VAL);
  EXPECT_FALSE(mh::cli::parse_number("--dt", "1e-3s").has_value());
  EXPECT_FALSE(mh::cli::parse_number("--dt", " 1").has_value());
}

TEST(CliSupport, LimitsMustBeFiniteAndAtLeastOne) {
  mh::RunLimits limits;
  EXPECT_TRUE(mh::cli::parse_limit("--max-steps", "1e9", limits));
  EXPECT_EQ(limits.max_steps, 1e9);
  EXPECT_TRUE(mh::cli::parse_limit("--max-output-bytes", "5e10", limits));
  EXPECT_EQ(limits.max_output_bytes, 5e10);
  EXPECT_FALSE(mh::cli::parse_limit("--max-steps", "0", limits));
  EXPECT_FALSE(mh::cli::parse_limit("--max-steps", "inf", limits));
  EXPECT_EQ(limits.max_steps, 1e9);
}

TEST(CliSupport, AFileCutMidRowIsCutBackToItsLastWholeRow) {
  const auto dir = mh::test::scratch_dir("cli-support");
  const auto csv = dir / "cut.csv";
  // The last whole row ends 5000 bytes before the end: more than one block back.
  std::ofstream(csv) << "t,z1\n0,1\n" << std::string(5000, '9');
  mh::cli::drop_partial_last_line(csv.string());
  EXPECT_EQ(mh::test::read_text(csv), "t,z1\n0,1\n");
  mh::cli::drop_partial_last_line(csv.string());  // whole rows stay
  EXPECT_EQ(mh::test::read_text(csv), "t,z1\n0,1\n");
}

}  // namespace
