// The monohydra command line, run as a user runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "cli_runner.hpp"
#include "monohydra/types.h"

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
  const std::string abi = "(ABI " + std::to_string(MH_ABI_VERSION_MAJOR) + "." +
                          std::to_string(MH_ABI_VERSION_MINOR) + "." +
                          std::to_string(MH_ABI_VERSION_PATCH) + ")";
  EXPECT_NE(r.output.find(abi), std::string::npos) << r.output;
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

TEST(MonohydraCli, UnknownCommandIsNamedInItsErrorWithTheCommandsThereAre) {
  const auto r = run_cli("frobnicate models/fourbar.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("unknown command 'frobnicate'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("plugins, run, compare, validate, sweep, check"), std::string::npos)
      << r.output;
  const auto option = run_cli("--frob");
  EXPECT_EQ(option.code, 2);
  EXPECT_NE(option.output.find("unknown command '--frob'"), std::string::npos) << option.output;
}

TEST(MonohydraCli, NonNumericFlagValueIsAUsageError) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --dt nope");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--dt expects a number, got 'nope'"), std::string::npos) << r.output;
}

// --- reliability: results never lost or faked, settings checked first ---------

using mh::test::run_shell;

bool contains(const CliResult& r, const std::string& text) {
  return r.output.find(text) != std::string::npos;
}

// A shipped model with `from` replaced by `to`, written to the scratch folder.
std::filesystem::path edited_model(const std::string& name, const std::string& from,
                                   const std::string& to, const std::string& as) {
  std::string text = mh::test::read_text(model(name));
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const auto path = temp_dir() / as;
  std::ofstream(path) << text;
  return path;
}

TEST(MonohydraCliReliability, CsvToAFullDeviceExitsOneAndNamesTheFile) {
  const CliResult r =
      run_cli("run " + model("double-pendulum.yaml") + " --t-end 0.5 --out /dev/full");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r,
                       "of 500: cannot write the results to '/dev/full': No space left on "
                       "device"))
      << r.output;
}

TEST(MonohydraCliReliability, StdoutToAFullDeviceExitsOne) {
  const CliResult r =
      run_shell("( MONOHYDRA_PLUGIN_PATH= " + std::string(mh::test::paths::executable) + " run " +
                model("double-pendulum.yaml") + " --t-end 0.01 >/dev/full )");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r, "monohydra: cannot write to standard output: No space left on device"))
      << r.output;
}

// Stops a long run with `signal` once its CSV has 200 rows.
CliResult interrupted_run(const std::string& signal, const std::filesystem::path& csv) {
  return run_shell("( MONOHYDRA_PLUGIN_PATH= " + std::string(mh::test::paths::executable) +
                   " run " + model("double-pendulum.yaml") + " --t-end 1e4 --out " + csv.string() +
                   " & p=$!; for i in $(seq 600); do [ \"$(cat " + csv.string() +
                   " 2>/dev/null | wc -l)\" -ge 200 ] && break; sleep 0.05; done; kill -" + signal +
                   " $p; wait $p )");
}

void expect_whole_rows(const std::filesystem::path& csv) {
  const std::string text = mh::test::read_text(csv);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const auto lines = read_lines(csv);
  const auto commas = [](const std::string& l) { return std::count(l.begin(), l.end(), ','); };
  for (const auto& l : lines) ASSERT_EQ(commas(l), commas(lines.front())) << l;
}

TEST(MonohydraCliReliability, SigintStopsAfterAWholeRowSaysWhereAndExits130) {
  const auto csv = temp_dir() / "sigint.csv";
  const CliResult r = interrupted_run("INT", csv);
  EXPECT_EQ(r.code, 130) << r.output;
  EXPECT_TRUE(contains(r, "monohydra: interrupted by SIGINT: stopped at t = ")) << r.output;
  EXPECT_TRUE(contains(r, " of 10000000; every row up to there is in '" + csv.string() + "'"))
      << r.output;
  expect_whole_rows(csv);
}

TEST(MonohydraCliReliability, SigtermStopsAfterAWholeRowAndExits143) {
  const auto csv = temp_dir() / "sigterm.csv";
  const CliResult r = interrupted_run("TERM", csv);
  EXPECT_EQ(r.code, 143) << r.output;
  EXPECT_TRUE(contains(r, "monohydra: interrupted by SIGTERM: stopped at t = ")) << r.output;
  expect_whole_rows(csv);
}

TEST(MonohydraCliReliability, StepCountOverflowIsRefusedBeforeRunning) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --t-end 1e19");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r,
                       "monohydra: command line: --t-end: t_end / dt = 1e+19 / 0.001 = 1e+22 "
                       "steps, above the limit of 1e+08 steps (raise it with --max-steps N)"))
      << r.output;
  EXPECT_FALSE(contains(r, "steps:")) << r.output;  // no run summary: nothing ran
}

TEST(MonohydraCliReliability, InfiniteEndTimeIsRefused) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --t-end inf");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r,
                       "--t-end: expected a positive finite end time in s (a run of zero steps "
                       "is an error), got inf"))
      << r.output;
}

TEST(MonohydraCliReliability, HugeEndTimeInTheModelIsRefusedAtItsLine) {
  const auto path = edited_model("double-pendulum.yaml", "t_end: 10", "t_end: 1e300", "t.yaml");
  const CliResult r = run_cli("run " + path.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":25:28: solver.t_end: t_end / dt = 1e+300 / 0.001"))
      << r.output;
}

TEST(MonohydraCliReliability, SubnormalTimeStepIsANumberRefusedWithItsRange) {
  const CliResult r = run_cli("run " + model("double-pendulum.yaml") + " --dt 1e-320");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(contains(r, "expects a number")) << r.output;
  EXPECT_TRUE(contains(r,
                       "--dt: expected a time step from 1e-09 s to t_end = 10 s, got "
                       "9.99989e-321"))
      << r.output;
}

TEST(MonohydraCliReliability, TinyTimeStepThatWouldRunForeverIsRefused) {
  const auto path = edited_model("double-pendulum.yaml", "dt: 0.001", "dt: 1e-12", "dt.yaml");
  const CliResult r = run_cli("run " + path.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":25:14: solver.dt: expected a time step from 1e-09 s "
                                          "to t_end = 10 s, got 1e-12"))
      << r.output;
}

TEST(MonohydraCliReliability, MaxStepsFlagMovesTheStepLimit) {
  const std::string args = "run " + model("double-pendulum.yaml") + " --t-end 0.25";
  const CliResult refused = run_cli(args + " --max-steps 100");
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_TRUE(contains(refused, "= 250 steps, above the limit of 100 steps")) << refused.output;
  const CliResult ran = run_cli(args + " --max-steps 250");
  EXPECT_EQ(ran.code, 0) << ran.output;
  EXPECT_TRUE(contains(ran, "steps:        250 of 250 asked")) << ran.output;
}

TEST(MonohydraCliReliability, OutputAboveTheLimitIsRefusedWithTheEstimate) {
  const auto csv = temp_dir() / "big.csv";
  const CliResult r =
      run_cli("run " + model("double-pendulum.yaml") + " --t-end 1e5 --out " + csv.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r,
                       "the CSV would take about 1.8e+10 bytes (1e+08 rows x 9 columns x ~20 "
                       "bytes), above the limit of 1e+10 bytes (raise it with "
                       "--max-output-bytes N)"))
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(csv));
}

TEST(MonohydraCliReliability, CompareRefusesAnOverflowingRunInsteadOfReportingZeroSteps) {
  const CliResult r = run_cli("compare " + model("double-pendulum.yaml") +
                              " --formulations open-loop --t-end 1e12");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, "1e+15 steps, above the limit of 1e+08 steps")) << r.output;
  EXPECT_FALSE(contains(r, "status")) << r.output;
}

TEST(MonohydraCliReliability, ValidateSaysOkWithoutRunning) {
  const CliResult r = run_cli("validate " + model("fourbar.yaml"));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output,
            "OK: " + model("fourbar.yaml") +
                " (fourbar, double-step, trapezoidal): 10000 steps of dt = 0.001 s, 19 columns\n");
}

TEST(MonohydraCliReliability, ValidateExitsOneWithTheError) {
  const CliResult r = run_cli("validate " + model("fourbar.yaml") + " --dt 1e-12");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r, "--dt: expected a time step from 1e-09 s")) << r.output;
}

TEST(MonohydraCliReliability, DevZeroAsModelIsRefusedBeforeReading) {
  const CliResult r = run_cli("validate /dev/zero");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r, "/dev/zero: cannot read the model file: not a regular file")) << r.output;
}

TEST(MonohydraCliReliability, ModelCutInHalfIsRefused) {
  const std::string text = mh::test::read_text(model("fourbar.yaml"));
  const auto path = temp_dir() / "half.yaml";
  const std::string half = text.substr(0, text.rfind('\n', text.size() / 2) + 1);
  std::ofstream(path) << half;
  const CliResult r = run_cli("validate " + path.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":")) << r.output;
  EXPECT_FALSE(contains(r, "OK:")) << r.output;
}

TEST(MonohydraCliReliability, AssemblyFixingEveryBodyIsAnErrorNotACrash) {
  const auto path = edited_model("crank-rocker.yaml", "assembly: {fixed: [crank]}",
                                 "assembly: {fixed: [crank, coupler, rocker]}", "fixed.yaml");
  const CliResult r = run_cli("run " + path.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":35:19: assembly.fixed: lists every body, so nothing "
                                          "can move"))
      << r.output;
}

TEST(MonohydraCliReliability, UnknownEquilibriumStateIsAnErrorNotAnAbort) {
  const auto path = edited_model("fourbar.yaml", "equilibrium: {free: [p1, p2]}",
                                 "equilibrium: {free: [p1, p2, nosuch]}", "eq.yaml");
  const CliResult r = run_cli("run " + path.string() + " --t-end 0.01");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":99:30: equilibrium.free: unknown state 'nosuch' "
                                          "(expected a state's result column or "
                                          "'instance.state' name: p1 (n1), p2 (n2)"))
      << r.output;
}

TEST(MonohydraCliReliability, UnknownStatesKeyIsRefused) {
  const auto path =
      edited_model("fourbar.yaml", "states: {U: U}", "states: {U: U, nosuch: x}", "st.yaml");
  const CliResult r = run_cli("run " + path.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, path.string() + ":63:20: subsystems[3].states.nosuch: unknown state "
                                          "'nosuch' (the valve-4-3 'valve' declares no such "
                                          "state)"))
      << r.output;
}

TEST(MonohydraCliReliability, StateColumnNamedLikeACoordinateIsRefused) {
  const auto path = edited_model("fourbar.yaml", "states: {U: U}", "states: {U: z1}", "z1.yaml");
  const CliResult r = run_cli("run " + path.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r, "subsystems[3].states.U: 'z1' is the coordinate column of body"))
      << r.output;
}

}  // namespace

namespace {

std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

// --set is the model file as if it wrote the value: the same rows to the
// byte as a copy of the file edited by hand, and the sidecar says what was set.
TEST(MonohydraCliSet, ARunWithSetIsTheRunOfTheFileEditedToTheSameValue) {
  const auto dir = temp_dir() / "set";
  std::filesystem::create_directories(dir);
  std::string text = file_text(model("fourbar.yaml"));
  const std::size_t at = text.find("mass: 50");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 8, "mass: 57.5");
  const auto edited = dir / "fourbar-edited.yaml";
  std::ofstream(edited) << text;
  const auto a = dir / "set.csv";
  const auto b = dir / "edited.csv";
  const auto c = dir / "nominal.csv";
  const CliResult set = run_cli("run " + model("fourbar.yaml") +
                                " --t-end 0.2 --set bodies/body3/mass=57.5 --out " + a.string());
  ASSERT_EQ(set.code, 0) << set.output;
  ASSERT_EQ(run_cli("run " + edited.string() + " --t-end 0.2 --out " + b.string()).code, 0);
  ASSERT_EQ(run_cli("run " + model("fourbar.yaml") + " --t-end 0.2 --out " + c.string()).code, 0);
  EXPECT_EQ(file_text(a), file_text(b));
  EXPECT_NE(file_text(a), file_text(c));  // and the value acts
  EXPECT_NE(file_text(dir / "set.meta.json")
                .find(R"("set": [{"path": "bodies/body3/mass", "value": "57.5"}])"),
            std::string::npos);
}

TEST(MonohydraCliSet, APathTheModelDoesNotHaveOrANonNumberIsRefusedNamingFileAndPath) {
  const CliResult missing =
      run_cli("run " + model("fourbar.yaml") + " --set subsystems/V9/bulk_modulus=1e9");
  EXPECT_EQ(missing.code, 2);
  EXPECT_TRUE(contains(missing,
                       "fourbar.yaml: --set subsystems/V9/bulk_modulus=1e9: no item "
                       "named 'V9' in subsystems (it has"))
      << missing.output;
  const CliResult word = run_cli("validate " + model("fourbar.yaml") + " --set gravity/1=down");
  EXPECT_EQ(word.code, 1);
  EXPECT_TRUE(contains(word, "--set gravity/1=down: expected a number")) << word.output;
  const CliResult malformed = run_cli("run " + model("fourbar.yaml") + " --set gravity");
  EXPECT_EQ(malformed.code, 2);
  EXPECT_TRUE(contains(malformed, "--set expects PATH=VALUE")) << malformed.output;
}

// The shipped four-bar's sensors made noiseless read the run's own columns at
// their rates: the readings against the run's CSV, row by row; an empty field
// where a sensor took none.
TEST(MonohydraCliSensors, SensorsOutWritesEachSensorsReadingsAtItsRateBesideTheRun) {
  const auto dir = temp_dir() / "sensors";
  std::filesystem::create_directories(dir);
  const CliResult r = run_cli("run " + model("fourbar.yaml") +
                              " --t-end 0.05 --set sensors/z1/noise=0 --set sensors/p2/noise=0"
                              " --out " +
                              (dir / "run.csv").string() + " --sensors-out " +
                              (dir / "sensors.csv").string() + " --seed 42");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto run = read_lines(dir / "run.csv");
  const auto sensors = read_lines(dir / "sensors.csv");
  ASSERT_EQ(sensors.size(), run.size());  // a row per step: crank has every one
  EXPECT_EQ(sensors[0], "t,z1,p1,p2,p3");
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) out.push_back(f);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
  };
  const std::vector<std::string> header = fields(run[0]);
  const auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  for (size_t i = 1; i < run.size(); ++i) {
    const auto s = fields(sensors[i]);
    const auto v = fields(run[i]);
    ASSERT_EQ(s.size(), 5u) << sensors[i];
    EXPECT_EQ(s[0], v[column("t")]);
    EXPECT_EQ(s[1], v[column("z1")]);
    EXPECT_EQ(s[3], (i - 1) % 10 == 0 ? v[column("p2")] : "") << sensors[i];
    if ((i - 1) % 10 == 0) {  // p1 with its noise: near, not equal
      EXPECT_NE(s[2], v[column("p1")]);
      EXPECT_NEAR(std::stod(s[2]), std::stod(v[column("p1")]), 5 * 3.8e4);
    }
  }
  EXPECT_NE(file_text(dir / "sensors.meta.json").find("\"sensor_seed\": 42"), std::string::npos);
}

TEST(MonohydraCliSensors, BadSensorsAndFlagsAreRefusedNamingWhat) {
  const auto path = temp_dir() / "bad-sensors";
  std::filesystem::create_directories(path);
  const CliResult column =
      run_cli("validate " + model("fourbar.yaml") + " --set sensors/p1/measures=p9");
  EXPECT_EQ(column.code, 1);
  EXPECT_TRUE(contains(column, "sensors[1].measures: unknown column 'p9'")) << column.output;
  const auto unwritten = path / "none.csv";
  const auto rows = path / "rows.csv";
  const CliResult none = run_cli("run " + model("double-pendulum.yaml") + " --t-end 0.01 --out " +
                                 rows.string() + " --sensors-out " + unwritten.string());
  EXPECT_EQ(none.code, 2);
  EXPECT_TRUE(contains(none, "has no sensors:")) << none.output;
  EXPECT_FALSE(std::filesystem::exists(unwritten));  // nothing half written
  EXPECT_FALSE(std::filesystem::exists(rows));
  // A 1 kHz encoder does not fit a 2 ms step: refused when read, not otherwise.
  const CliResult coarse =
      run_cli("run " + model("fourbar.yaml") + " --t-end 0.01 --dt 0.002 --sensors-out " +
              (path / "coarse.csv").string());
  EXPECT_EQ(coarse.code, 2);
  EXPECT_TRUE(contains(coarse,
                       "sensors[0].rate: expected a rate whose period 1/rate is a whole "
                       "number of steps dt = 0.002 s, got 1000 Hz"))
      << coarse.output;
  EXPECT_EQ(run_cli("validate " + model("fourbar.yaml") + " --dt 0.002").code, 0);
  const CliResult seed = run_cli("run " + model("fourbar.yaml") + " --seed 3");
  EXPECT_EQ(seed.code, 2);
  EXPECT_TRUE(contains(seed, "--seed applies to --sensors-out only")) << seed.output;
}
