// `monohydra run`'s output choices (output: in the model file,
// --output-interval) and its real-time mode, run as a user runs them; and
// that every mode but real time gives the same bytes run after run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::read_csv;
using mh::test::read_text;
using mh::test::run_cli;

std::filesystem::path dir() {
  return mh::test::scratch_dir("run-output");
}

// The double pendulum with `extra` appended (e.g. an output: block).
std::string pendulum_with(const std::filesystem::path& folder, const std::string& extra) {
  const auto path = folder / "pendulum.yaml";
  std::ofstream(path) << read_text(mh::test::shipped_model("double-pendulum.yaml")) << extra;
  return path.string();
}

TEST(RunOutput, OutputIntervalWritesTheEveryStepRowsAtItsMultiplesOnly) {
  const auto d = dir();
  const std::string model = mh::test::shipped_model("double-pendulum.yaml");
  ASSERT_EQ(run_cli("run " + model + " --t-end 0.5 --out " + (d / "all.csv").string()).code, 0);
  const CliResult r = run_cli("run " + model + " --t-end 0.5 --output-interval 0.01 --out " +
                              (d / "sparse.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("51 rows of 9 columns, every 10 steps"), std::string::npos) << r.output;
  std::ifstream all(d / "all.csv"), sparse(d / "sparse.csv");
  std::string a, s;
  std::getline(all, a);
  std::getline(sparse, s);
  EXPECT_EQ(a, s);  // the same columns
  int rows = 0;
  for (int k = 0; std::getline(all, a); ++k) {
    if (k % 10 != 0) continue;
    ASSERT_TRUE(std::getline(sparse, s)) << "row of step " << k << " missing";
    EXPECT_EQ(a, s) << "step " << k;  // the very same row, bit for bit
    ++rows;
  }
  EXPECT_EQ(rows, 51);
  EXPECT_FALSE(std::getline(sparse, s)) << "extra row: " << s;
}

TEST(RunOutput, ModelFileSelectsColumnsInItsOrderAndInterval) {
  const auto d = dir();
  const std::string model = pendulum_with(d, "output: {interval: 0.05, columns: [t, z2, KE]}\n");
  const CliResult r = run_cli("run " + model + " --t-end 0.5 --out " + (d / "o.csv").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto csv = read_csv(d / "o.csv");
  EXPECT_EQ(csv.header, (std::vector<std::string>{"t", "z2", "KE"}));
  ASSERT_EQ(csv.rows, 11u);
  for (size_t i = 0; i < csv.rows; ++i)
    EXPECT_NEAR(csv["t"][i], 0.05 * static_cast<double>(i), 1e-12);
  // --output-interval overrides the file's interval.
  const CliResult r2 = run_cli("run " + model + " --t-end 0.5 --output-interval 0.1 --out " +
                               (d / "o2.csv").string());
  ASSERT_EQ(r2.code, 0) << r2.output;
  EXPECT_EQ(read_csv(d / "o2.csv").rows, 6u);
}

TEST(RunOutput, UnknownColumnIsRefusedWithItsLineAndTheColumnsTheRunWrites) {
  const auto d = dir();
  const std::string model = pendulum_with(d, "output:\n  columns: [t, p9]\n");
  const CliResult r = run_cli("run " + model + " --t-end 0.1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("pendulum.yaml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("output.columns[1]: unknown column 'p9' (this run writes: t, z1, z2, "
                          "KE, PE, W, drift, phi_norm, iters)"),
            std::string::npos)
      << r.output;
  // validate refuses what run refuses.
  EXPECT_EQ(run_cli("validate " + model).code, 1);
}

TEST(RunOutput, IntervalThatIsNotAWholeNumberOfStepsIsRefused) {
  const auto d = dir();
  const CliResult r = run_cli("run " + mh::test::shipped_model("double-pendulum.yaml") +
                              " --t-end 0.1 --output-interval 0.0015");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--output-interval: expected a whole multiple of the time step dt = "
                          "0.001 s, got 0.0015 s (1.5 steps)"),
            std::string::npos)
      << r.output;
  const std::string model = pendulum_with(d, "output: {interval: -1}\n");
  const CliResult r2 = run_cli("run " + model + " --t-end 0.1");
  EXPECT_EQ(r2.code, 2) << r2.output;
  EXPECT_NE(r2.output.find("output.interval: expected a positive finite number"), std::string::npos)
      << r2.output;
  EXPECT_EQ(run_cli("run " + model + " --output-interval 0").code, 2);
}

// Every mode but real time is deterministic: the same CSV bytes twice, with
// each linear solver and with modified Newton.
TEST(RunOutput, EveryModeButRealTimeGivesTheSameBytesRunAfterRun) {
  const auto d = dir();
  const std::string src = read_text(mh::test::shipped_model("fourbar.yaml"));
  const auto at = src.rfind("solver: {");
  ASSERT_NE(at, std::string::npos) << "fourbar.yaml ends with its solver: {...} line";
  for (const char* choice :
       {"linear: klu", "linear: umfpack", "linear: dense", "newton: modified"}) {
    std::string text = src;
    text.insert(at + 9, std::string(choice) + ", ");
    const auto model = d / "fourbar.yaml";
    std::ofstream(model) << text;
    std::string bytes[2];
    for (int run = 0; run < 2; ++run) {
      const auto csv = d / ("run" + std::to_string(run) + ".csv");
      const CliResult r = run_cli("run " + model.string() +
                                  " --formulation penalty --t-end 1 --out " + csv.string());
      ASSERT_EQ(r.code, 0) << choice << "\n" << r.output;
      bytes[run] = read_text(csv);
    }
    EXPECT_GT(bytes[0].size(), 1000u) << choice;
    EXPECT_TRUE(bytes[0] == bytes[1]) << choice << ": two runs differ";
  }
}

TEST(RunOutput, RealTimeRunPacesToTheWallClockAndAccountsForItsDeadlines) {
  const auto d = dir();
  const auto csv = d / "rt.csv";
  const CliResult r = run_cli("run " + mh::test::shipped_model("fourbar.yaml") +
                              " --t-end 0.3 --real-time --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("deadlines missed: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("accepted unconverged: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("these results depend on this machine's speed and load"),
            std::string::npos)
      << r.output;
  const auto rows = read_csv(csv);
  ASSERT_EQ(rows.header.back(), "unconverged");
  ASSERT_EQ(rows.header[rows.header.size() - 2], "late");
  ASSERT_EQ(rows.rows, 301u);
  for (size_t i = 0; i < rows.rows; ++i) {
    EXPECT_GE(rows["late"][i], 0.0);
    EXPECT_GE(rows["unconverged"][i], 0.0);
  }
  // Paced: the last step (0.299 s to 0.3 s) starts no earlier than 0.299 s
  // of wall time after the first.
  const auto wall = r.output.find("wall time:    ");
  ASSERT_NE(wall, std::string::npos) << r.output;
  EXPECT_GE(std::stod(r.output.substr(wall + 14)), 0.299) << r.output;
}

TEST(RunOutput, RealTimeIterationCapAcceptsUnconvergedStepsAndCountsThem) {
  const auto d = dir();
  const auto csv = d / "cap.csv";
  // One iteration per step: once the valve opens (t = 1 s), steps that full
  // Newton needs two for are accepted after one, and counted.
  const CliResult r = run_cli("run " + mh::test::shipped_model("fourbar.yaml") +
                              " --formulation penalty --t-end 1.5 --real-time --newton-cap 1 "
                              "--out " +
                              csv.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = read_csv(csv);
  int unconverged = 0;
  for (size_t i = 0; i < rows.rows; ++i) {
    EXPECT_LE(rows["iters"][i], 1.0);
    if (rows["unconverged"][i] > 0.0) ++unconverged;
  }
  EXPECT_GT(unconverged, 0);
  const std::string expect = "accepted unconverged: " + std::to_string(unconverged) + " steps";
  EXPECT_NE(r.output.find(expect), std::string::npos) << expect << "\n" << r.output;
  EXPECT_EQ(run_cli("run " + mh::test::shipped_model("fourbar.yaml") + " --newton-cap 2").code, 2);
  EXPECT_EQ(
      run_cli("run " + mh::test::shipped_model("fourbar.yaml") + " --real-time --newton-cap 0")
          .code,
      2);
}

}  // namespace
