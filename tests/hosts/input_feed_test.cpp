// run --inputs FILE.csv | - and --stream (hosts/monohydra/input_feed.cpp):
// the four-bar's valve driven by a CSV time series of its own table gives the
// table's CSV byte for byte; lines name=value on standard input are applied
// before the next step, a bad one reported with its number and skipped; a bad
// CSV is refused before the run with file and line; --stream writes the rows
// --out would, on standard output.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "build_paths.hpp"
#include "cli_runner.hpp"

namespace mh::test {
namespace {

// The four-bar's valve_command table as held values: rows at its jumps.
const char* kValveSeries = "t,valve_command\n0,0\n1,10\n2.5,0\n5,-10\n8,0\n";

TEST(RunInputs, ACsvSeriesOfTheValvesTableGivesTheTablesResultsByteForByte) {
  const auto dir = scratch_dir("inputs-csv");
  std::ofstream(dir / "valve.csv") << kValveSeries;
  const std::string m = shipped_model("fourbar.yaml");
  ASSERT_EQ(run_cli("run " + m + " --out " + (dir / "table.csv").string()).code, 0);
  const CliResult fed = run_cli("run " + m + " --inputs " + (dir / "valve.csv").string() +
                                " --out " + (dir / "fed.csv").string());
  ASSERT_EQ(fed.code, 0) << fed.output;
  EXPECT_EQ(read_text(dir / "fed.csv"), read_text(dir / "table.csv"));
}

TEST(RunInputs, StandardInputLinesApplyAtTheNextStepAndBadLinesAreNamedAndSkipped) {
  const auto dir = scratch_dir("inputs-stdin");
  const std::string m = shipped_model("fourbar.yaml") + " --t-end 0.5";
  std::ofstream(dir / "held.csv") << "t,valve_command\n0,5\n";
  ASSERT_EQ(run_cli("run " + m + " --inputs " + (dir / "held.csv").string() + " --out " +
                    (dir / "held-out.csv").string())
                .code,
            0);
  // A file on standard input is read whole before the first step.
  std::ofstream(dir / "lines.txt") << "# an operator's levers\nvalve_command=12\nboom=3\n"
                                      "valve_command=abc\nvalve_command = 5\n";
  const CliResult fed =
      run_cli("run " + m + " --inputs - --out " + (dir / "stdin-out.csv").string() + " < " +
              (dir / "lines.txt").string());
  ASSERT_EQ(fed.code, 0) << fed.output;
  EXPECT_NE(fed.output.find("--inputs -: line 2: input 'valve_command': 12 V is outside its range"),
            std::string::npos)
      << fed.output;
  EXPECT_NE(fed.output.find("--inputs -: line 3: no input 'boom' (the model's inputs: "
                            "valve_command); ignored"),
            std::string::npos)
      << fed.output;
  EXPECT_NE(fed.output.find("line 4: expected a finite number"), std::string::npos) << fed.output;
  EXPECT_EQ(read_text(dir / "stdin-out.csv"), read_text(dir / "held-out.csv"));
}

TEST(RunInputs, ABadCsvIsRefusedBeforeTheRunWithFileAndLine) {
  const auto dir = scratch_dir("inputs-bad");
  const std::string m = shipped_model("fourbar.yaml");
  const auto refused = [&](const std::string& text, const std::string& expected) {
    std::ofstream(dir / "bad.csv") << text;
    const CliResult r = run_cli("run " + m + " --inputs " + (dir / "bad.csv").string());
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << text << "\n" << r.output;
  };
  refused("time,valve_command\n0,1\n", "bad.csv:1:1: header: a header 't,NAME,...'");
  refused("t,boom\n0,1\n", "bad.csv:1: header column 2: one of the model's inputs (valve_command)");
  refused("t,valve_command\n0,1\n0.5\n", "bad.csv:3: row: 2 cells as the header has, got 1");
  refused("t,valve_command\n1,1\n0.5,2\n", "bad.csv:3:1: t: a finite time (s), not before");
  refused("t,valve_command\n0,nan\n", "bad.csv:2: valve_command: a finite number");
  refused("t,valve_command\n0,11\n",
          "bad.csv:2: valve_command: input 'valve_command': 11 V is outside");
}

TEST(RunStream, WritesTheRowsOfOutOnStandardOutputAndTheSummaryOnStandardError) {
  const auto dir = scratch_dir("stream");
  const std::string m = shipped_model("fourbar.yaml") + " --t-end 0.2";
  ASSERT_EQ(run_cli("run " + m + " --out " + (dir / "out.csv").string()).code, 0);
  // In a subshell: run_shell's own 2>&1 comes after it and must not join the two.
  const CliResult streamed =
      run_shell(std::string("(MONOHYDRA_PLUGIN_PATH= ") + mh::test::paths::executable + " run " +
                m + " --stream > " + (dir / "stream.csv").string() + " 2> " +
                (dir / "summary.txt").string() + ")");
  ASSERT_EQ(streamed.code, 0) << read_text(dir / "summary.txt");
  EXPECT_EQ(read_text(dir / "stream.csv"), read_text(dir / "out.csv"));
  EXPECT_NE(read_text(dir / "summary.txt").find("steps:        200 of 200"), std::string::npos);
  const CliResult both = run_cli("run " + m + " --stream --out " + (dir / "x.csv").string());
  EXPECT_EQ(both.code, 2) << both.output;
}

}  // namespace
}  // namespace mh::test
