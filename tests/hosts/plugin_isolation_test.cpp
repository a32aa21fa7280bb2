// A plugin cannot take the command line down: `plugins` lists the libraries
// that crash while loading as refused, and `compare` keeps every other run's
// results, and the rows before, when a formulation crashes in its run.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "build_paths.hpp"
#include "cli_runner.hpp"
#include "printed_table.hpp"

namespace mh::test {
namespace {

namespace fs = std::filesystem;

const std::string kFaulty = mh::test::paths::faulty_plugin_dir;
// The faulty folder first, then the build's plugins; no probe cache.
const std::string kEnv = "MONOHYDRA_PROBE_CACHE=off MONOHYDRA_PLUGIN_PATH=" + kFaulty + " ";

TEST(PluginIsolation, PluginsListsTheGoodOnesAndEachCrashingLibraryAsRefusedWithItsReason) {
  const CliResult r = run_cli("plugins", kEnv);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(
      r.output.find("  formulation  crashing-formulation Crashing formulation (test) (v1.0.0)"),
      std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("  formulation  double-step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  integrator   trapezoidal"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refused: '" + kFaulty +
                          "/crash_in_init.so' crashed with SIGSEGV during probing, in its init\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("refused: '" + kFaulty +
                          "/huge_count.so' claims 4294967295 formulation components (at most "
                          "10000)\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(
      r.output.find("refused: '" + kFaulty +
                    "/truncated_plugin.so' crashed with SIGBUS during probing, while loading (its "
                    "constructors)\n"),
      std::string::npos)
      << r.output;
}

TEST(PluginIsolation, CompareKeepsTheOtherRunsAndTheRowsBeforeWhenAFormulationCrashes) {
  const fs::path dir = scratch_dir("crashing");
  const CliResult r = run_cli("compare " + shipped_model("fourbar-free.yaml") +
                                  " --formulations double-step,crashing-formulation,penalty "
                                  "--t-end 0.5 --report " +
                                  (dir / "report").string(),
                              kEnv);
  EXPECT_EQ(r.code, 1) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("status", "double-step"), "ok");
  EXPECT_EQ(t.cell("status", "crashing-formulation"), "crashed (SIGSEGV) after t = 0.1 s");
  EXPECT_EQ(t.cell("status", "penalty"), "ok");
  EXPECT_EQ(t.cell("steps", "double-step"), "500");
  EXPECT_EQ(t.cell("steps", "crashing-formulation"), "100");  // t = 0.001 .. 0.1
  EXPECT_EQ(t.cell("steps", "penalty"), "500");
  EXPECT_NE(r.output.find("monohydra: crashing-formulation failed on fourbar-free: crashed "
                          "(SIGSEGV) after t = 0.1 s; in formulation 'crashing-formulation' of "
                          "crashing_formulation.so, in its residual, at t = 0.101 s, step 101\n"),
            std::string::npos)
      << r.output;
  // The CSVs hold every run's rows, the crashed one's up to its last row.
  EXPECT_EQ(read_csv(dir / "report" / "double-step.csv").rows, 501u);
  const Csv crashed = read_csv(dir / "report" / "crashing-formulation.csv");
  ASSERT_EQ(crashed.rows, 101u);
  EXPECT_NEAR(crashed["t"].back(), 0.1, 1e-12);
  EXPECT_EQ(read_csv(dir / "report" / "penalty.csv").rows, 501u);
  const std::string html = read_text(dir / "report" / "report.html");
  EXPECT_NE(html.find("crashed (SIGSEGV) after t = 0.1 s"), std::string::npos);
}

// `run` steps in a child too: the crash ends the child, the host says where,
// and the CSV keeps every row computed (it is flushed row by row).
TEST(PluginIsolation, RunSaysWhereAFormulationCrashedAndKeepsEveryRowBefore) {
  const fs::path dir = scratch_dir("run-crashing");
  const fs::path csv = dir / "out.csv";
  const CliResult r =
      run_cli("run " + shipped_model("fourbar-free.yaml") +
                  " --formulation crashing-formulation --t-end 0.5 --out " + csv.string(),
              kEnv);
  EXPECT_EQ(r.code, 1) << r.output;
  // The instance, its library, the call in flight, the time and step it
  // attempted, and where the rows are.
  EXPECT_NE(r.output.find("monohydra: the run crashed (SIGSEGV) in formulation "
                          "'crashing-formulation' of crashing_formulation.so, in its residual, at "
                          "t = 0.101 s, step 101; every row up to t = 0.1 s is in '" +
                          csv.string() + "'"),
            std::string::npos)
      << r.output;
  const Csv rows = read_csv(csv);
  ASSERT_EQ(rows.rows, 101u);  // t = 0 .. 0.1: none lost
  EXPECT_NEAR(rows["t"].back(), 0.1, 1e-12);
  EXPECT_EQ(read_text(csv).back(), '\n');
}

// SIGTERM reaches the parent only; it passes it on to the run's process.
TEST(PluginIsolation, SigtermToCompareStopsTheRunInItsProcessAndExits143) {
  const fs::path dir = scratch_dir("sigterm");
  const fs::path csv = dir / "double-step.csv";
  const CliResult r = run_shell(
      "( MONOHYDRA_PROBE_CACHE=off MONOHYDRA_PLUGIN_PATH= " +
      std::string(mh::test::paths::executable) + " compare " + shipped_model("fourbar-free.yaml") +
      " --formulations double-step,penalty --t-end 1e4 --report " + dir.string() +
      " & p=$!; for i in $(seq 600); do [ \"$(cat " + csv.string() +
      " 2>/dev/null | wc -l)\" -ge 200 ] && break; sleep 0.05; done; kill -TERM $p; wait $p )");
  EXPECT_EQ(r.code, 143) << r.output;
  EXPECT_NE(r.output.find("monohydra: interrupted by SIGTERM\n"), std::string::npos) << r.output;
  const PrintedTable t = parse_printed_table(r.output, "fourbar-free (");
  ASSERT_TRUE(t.found) << r.output;
  EXPECT_EQ(t.cell("status", "double-step").rfind("FAILED at t = ", 0), 0u) << r.output;
  EXPECT_EQ(t.cell("status", "penalty"), "");  // never started
  EXPECT_EQ(std::to_string(read_csv(csv).rows - 1), t.cell("steps", "double-step"));
}

// Every library built broken on purpose, each alone on the plugin path
// beside a run that does not use it (a bystander): probed in a child, it is
// refused or known and left alone, and the four-bar's rows are the clean
// run's byte for byte, from run and from linearize alike. (The library that
// hangs in its init is left out: its probe's 10 s limit is tested by
// PluginProbe.KillsALibraryThatHangsInInitAfterTheTimeLimit.)
TEST(PluginIsolation, EveryFaultyLibraryAsABystanderLeavesTheRunsResultsUnchanged) {
  const fs::path dir = scratch_dir("bystanders");
  const std::string fourbar = shipped_model("fourbar.yaml");
  const auto rows = [&](const std::string& env, const std::string& name) {
    const fs::path csv = dir / (name + ".csv");
    const CliResult r = run_cli("run " + fourbar + " --t-end 0.05 --out " + csv.string(), env);
    return std::make_pair(r, read_text(csv));
  };
  // linearize's matrices, from its states on (a refused bystander's warning comes before).
  const auto from_states = [](const std::string& out) {
    const size_t at = out.find("\nstates:");
    return at == std::string::npos ? std::string() : out.substr(at);
  };
  // A cache of this test's own: each library is probed in a child once, when
  // its run loads it, and its verdict serves the linearization after.
  const std::string cache = "MONOHYDRA_PROBE_CACHE=" + (dir / "probe-cache").string() + " ";
  const auto clean = rows(cache, "clean");
  ASSERT_EQ(clean.first.code, 0) << clean.first.output;
  const CliResult clean_linearized = run_cli("linearize " + fourbar + " --at 0.05", cache);
  ASSERT_EQ(clean_linearized.code, 0) << clean_linearized.output;
  size_t bystanders = 0;
  for (const char* folder :
       {mh::test::paths::faulty_plugin_dir, mh::test::paths::check_fixture_dir,
        mh::test::paths::boundary_plugin_dir, mh::test::paths::sdk20_plugin_dir,
        mh::test::paths::fixture_dir, mh::test::paths::clash_plugin_dir}) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() != ".so") continue;
      const std::string name = entry.path().stem().string();
      const fs::path alone = dir / ("path-" + name);
      fs::create_directories(alone);
      fs::create_symlink(entry.path(), alone / entry.path().filename());
      const std::string env = cache + "MONOHYDRA_PLUGIN_PATH=" + alone.string() + " ";
      const auto ran = rows(env, name);
      // A library offering an id the model uses is no bystander: the model
      // must say which it means, and the run is refused saying so.
      if (ran.first.output.find("is offered by 2 libraries") != std::string::npos) {
        EXPECT_EQ(ran.first.code, 2) << name << ": " << ran.first.output;
        continue;
      }
      ++bystanders;
      EXPECT_EQ(ran.first.code, 0) << name << ": " << ran.first.output;
      EXPECT_EQ(ran.second, clean.second) << name << ": its rows differ from the clean run's";
      const CliResult linearized = run_cli("linearize " + fourbar + " --at 0.05", env);
      EXPECT_EQ(linearized.code, 0) << name << ": " << linearized.output;
      EXPECT_EQ(from_states(linearized.output), from_states(clean_linearized.output)) << name;
      EXPECT_NE(from_states(linearized.output), "") << name << ": " << linearized.output;
    }
  }
  EXPECT_GE(bystanders, 40u);  // the corpus, as it stands
}

}  // namespace
}  // namespace mh::test
