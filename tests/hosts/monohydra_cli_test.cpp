// The monohydra command line, run as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;

std::string model(const std::string& name) {
  return mh::test::shipped_model(name);
}

std::filesystem::path temp_dir() {
  return mh::test::scratch_dir("cli");
}

std::vector<std::string> read_lines(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

TEST(MonohydraCli, PluginsListsEveryComponentWithKindAndAbiVersion) {
  const CliResult r = run_cli("plugins");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("(ABI 2.1.0)"), std::string::npos) << r.output;
  for (const char* line :
       {"formulation  open-loop", "subsystem    spring-damper", "subsystem    maxwell",
        "integrator   trapezoidal", "integrator   generalized-alpha", "integrator   bdf2"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
}

TEST(MonohydraCli, RunWritesTheDocumentedColumnsAndOneRowPerStep) {
  const auto csv = temp_dir() / "pendulum.csv";
  const CliResult r =
      run_cli("run " + model("double-pendulum.yaml") + " --t-end 0.25 --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto lines = read_lines(csv);
  ASSERT_EQ(lines.size(), 1u + 251u);
  EXPECT_EQ(lines[0], "t,z1,z2,KE,PE,W,drift,phi_norm,iters");
  // Last row: t = 0.25 and the energy columns balance: drift = KE + PE - W.
  std::stringstream ss(lines.back());
  std::vector<double> v;
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  ASSERT_EQ(v.size(), 9u);
  EXPECT_NEAR(v[0], 0.25, 1e-12);
  EXPECT_NEAR(v[6], v[3] + v[4] - v[5], 1e-12);
  EXPECT_GT(v[3], 1.0);  // it moved: kinetic energy of the fall
  EXPECT_GE(v[8], 1.0);  // iterations
}

TEST(MonohydraCli, SubsystemStatesAppearAsNamedColumns) {
  const auto csv = temp_dir() / "maxwell.csv";
  const CliResult r =
      run_cli("run " + model("maxwell-pendulum.yaml") + " --t-end 0.01 --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(read_lines(csv)[0], "t,z1,delta,KE,PE,W,drift,phi_norm,iters");
}

TEST(MonohydraCli, BadModelFileExitsWithTwoAndNamesFileLineAndField) {
  const auto bad = temp_dir() / "bad.yaml";
  std::ofstream(bad) << "units: {length: m, mass: kg, time: s, angle: rad}\n"
                        "bodies:\n"
                        "  - name: a\n"
                        "    parent: ground\n"
                        "    joint: {type: helical, at: [0, 0, 0], axis: [0, 0, 1]}\n"
                        "    mass: 1\n"
                        "    inertia: [1, 1, 1]\n";
  const CliResult r = run_cli("run " + bad.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find(bad.string() + ":5:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bodies[0].joint.type"), std::string::npos) << r.output;
}

TEST(MonohydraCli, UnknownFormulationExitsWithTwoAndListsTheKnownOnes) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --formulation lagrange");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("unknown formulation 'lagrange' (found: "), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("open-loop"), std::string::npos) << r.output;
}

TEST(MonohydraCli, FailedRunExitsWithOneNamesTheStepAndKeepsEarlierRows) {
  const auto dir = temp_dir();
  const auto bad = dir / "stiff.yaml";
  // Newton cannot meet a 1e-300 tolerance in one iteration: the run must stop
  // at step 1 and keep the row of t = 0.
  std::ofstream(bad) << "units: {length: m, mass: kg, time: s, angle: rad}\n"
                        "bodies:\n"
                        "  - name: rod\n"
                        "    parent: ground\n"
                        "    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}\n"
                        "    mass: 1\n"
                        "    shape: {type: beam, length: 1}\n"
                        "solver: {dt: 0.001, t_end: 1, max_iterations: 1, tol_position: 1e-300}\n";
  const auto csv = dir / "stiff.csv";
  const CliResult r = run_cli("run " + bad.string() + " --out " + csv.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("simulation failed at t = 0.001 s, step 1: Newton did not converge"),
            std::string::npos)
      << r.output;
  const auto lines = read_lines(csv);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1].rfind("0,0,0,", 0), 0u) << lines[1];
}

TEST(MonohydraCli, NonNumericFlagValueIsAUsageError) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --dt nope");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--dt expects a number, got 'nope'"), std::string::npos) << r.output;
}

}  // namespace
