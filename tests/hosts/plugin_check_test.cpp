// `monohydra check`: passes on sound plugins (shipped and a test spring) and
// fails, naming the check and the reason, on plugins broken on purpose
// (tests/fixtures/faulty/faulty_spring.c and the ABI fixtures).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "build_paths.hpp"
#include "cli_runner.hpp"
#include "monohydra/types.h"

namespace {

using mh::test::CliResult;
using mh::test::run_cli;
using mh::test::run_shell;

std::string fixture(const std::string& name) {
  return std::string(mh::test::paths::check_fixture_dir) + "/" + name + ".so";
}

// A pendulum on the faulty spring, swinging through a range of stretches.
std::string spring_model() {
  const auto path = mh::test::scratch_dir("check-model") / "faulty-spring.yaml";
  std::ofstream(path) << "units: {length: m, mass: kg, time: s, angle: rad}\n"
                         "gravity: [0, -9.81, 0]\n"
                         "bodies:\n"
                         "  - {name: link, parent: ground, joint: {type: revolute, at: [0, 0, 0],"
                         " axis: [0, 0, 1]}, mass: 1.0, shape: {type: beam, length: 1.0}}\n"
                         "subsystems:\n"
                         "  - name: spring\n"
                         "    type: faulty-spring\n"
                         "    stiffness: 40\n"
                         "    points: {a: {body: link, at: [1, 0, 0]}, b: {body: ground, at: [1, "
                         "-1, 0]}}\n"
                         "formulation: open-loop\n"
                         "solver: {dt: 0.001, t_end: 1}\n";
  return path.string();
}

// The pendulum of spring_model() written to `path`, its spring from the
// fixture `name` (tests/fixtures/faulty/faulty_spring.c).
void write_spring_model_with(const std::filesystem::path& path, const std::string& name) {
  std::ifstream in(spring_model());
  std::ofstream out(path);
  out << in.rdbuf() << "plugins: {faulty-spring: " << fixture(name) << "}\n";
}

// The time (its text) of the last row of a run's CSV.
std::string last_row_time(const std::filesystem::path& csv) {
  std::ifstream rows(csv);
  std::string line, last;
  while (std::getline(rows, line))
    if (!line.empty()) last = line;
  return last.substr(0, last.find(','));
}

TEST(PluginCheck, AShippedFormulationPassesEveryCheckOnTheFourBar) {
  const CliResult r =
      run_cli("check " + std::string(mh::test::paths::plugin_dir) + "/monohydra-penalty.so");
  ASSERT_EQ(r.code, 0) << r.output;
  // The plugin was built against this SDK: its ABI is the header's.
  const std::string abi = "ok    load: ABI " + std::to_string(MH_ABI_VERSION_MAJOR) + "." +
                          std::to_string(MH_ABI_VERSION_MINOR) + ".";
  for (const std::string& line : std::vector<std::string>{
           abi, "ok    formulation penalty: descriptor",
           "ok    formulation penalty: create/setup/destroy x3",
           "ok    formulation penalty: bad options refused",
           "ok    formulation penalty: analytic tangent against differences of its residual",
           "ok    formulation penalty: repeated runs bit-identical", "monohydra check: OK"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  EXPECT_NE(r.output.find("fourbar.yaml"), std::string::npos) << r.output;
}

TEST(PluginCheck, AFormulationForTreesOnlyIsCheckedOnATree) {
  const CliResult r =
      run_cli("check " + std::string(mh::test::paths::plugin_dir) + "/monohydra-open-loop.so");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("double-pendulum.yaml"), std::string::npos) << r.output;
}

TEST(PluginCheck, ASoundSubsystemPassesOnTheModelGiven) {
  const CliResult r = run_cli("check " + fixture("sound") + " " + spring_model());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok    subsystem faulty-spring: analytic tangent"), std::string::npos)
      << r.output;
}

// The snapshot check (state.h): a run saved at half the check's steps and
// restored into a fresh run must repeat the rest to the last bit.
TEST(PluginCheck, AFormulationWhoseSavedStateForgetsWhatItsNextStepReadsFails) {
  const CliResult r = run_cli("check " + fixture("forgetful_state"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  formulation forgetful-formulation: a snapshot restored into a "
                          "fresh run repeats its steps: the run restored from a snapshot at t = "
                          "0.01 s differs from the run it was saved from at t = 0.011 s"),
            std::string::npos)
      << r.output;
}

TEST(PluginCheck, AFormulationThatCannotSaveItsStateIsSkippedSayingWhy) {
  const CliResult r = run_cli("check " + std::string(mh::test::paths::faulty_plugin_dir) +
                              "/crashing_formulation.so");
  EXPECT_NE(r.output.find("skip  formulation crashing-formulation: a snapshot restored into a "
                          "fresh run repeats its steps: formulation 'crashing-formulation' of "
                          "crashing_formulation.so keeps state between steps and cannot save it "
                          "(it offers no monohydra.state/3 extension"),
            std::string::npos)
      << r.output;
}

TEST(PluginCheck, EveryShippedFormulationAndIntegratorPassesTheSnapshotCheck) {
  for (const char* library : {"monohydra-open-loop", "monohydra-double-step", "monohydra-penalty",
                              "monohydra-integrators"}) {
    const CliResult r =
        run_cli("check " + std::string(mh::test::paths::plugin_dir) + "/" + library + ".so");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("a snapshot restored into a fresh run repeats its steps"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("skip  "), std::string::npos) << r.output;
  }
}

TEST(PluginCheck, ATangentBlockThatDisagreesWithItsResidualFails) {
  const CliResult r = run_cli("check " + fixture("wrong_jacobian") + " " + spring_model());
  EXPECT_EQ(r.code, 1) << r.output;
  // Its point force jacobian has the wrong sign: K's entry is off by 2k
  // (k = 40 N/m at the link's tip, 1 m out), seen in the assembled tangent at
  // the coarse step, where c_a M' no longer hides K.
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: analytic tangent against differences "
                          "of its residual: the analytic tangent disagrees with differences of "
                          "the residual: at a step of 0.1 s: row mechanical unknown 1, column "
                          "mechanical unknown 1: analytic 93.38"),
            std::string::npos)
      << r.output;
  // Its own block says so directly, in its units and by the point's name:
  // dF/dp is -k, not +k (k = 40 N/m), from the first instant on.
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: its derivative blocks against "
                          "differences of its evaluate: dF/dp of subsystem 'spring' disagrees "
                          "with differences of its evaluate at t = 0 s: row force on point a z, "
                          "column point a z: analytic 40, differences -40"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("monohydra check: FAILED (2 failures)"), std::string::npos) << r.output;
}

// Errors a plugin author planted in a tangent when check compared each row at
// its largest entry, and that it passed: each now fails on the four-bar at its
// own dt, naming the block, the row and the column.
struct PlantedError {
  const char* fixture;
  const char* expected;
};

class BrokenTangent : public ::testing::TestWithParam<PlantedError> {};

TEST_P(BrokenTangent, FailsTheCheckOnTheFourBarAtItsOwnDt) {
  const CliResult r = run_cli("check " + fixture(GetParam().fixture) + " " +
                              mh::test::shipped_model("fourbar.yaml"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find(GetParam().expected), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("monohydra check: FAILED"), std::string::npos) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    PluginCheck, BrokenTangent,
    ::testing::Values(
        // K = d(M' zdd - Q')/dz dropped, or ten times over: dr/dx at the
        // four-bar's crank row; S = d(Phi_z^T lambda)/dz dropped: the same block.
        PlantedError{"tangent_k_zero",
                     "FAIL  formulation lagrange-baumgarte-broken: its tangent blocks against "
                     "differences of its residual in x, xd, xdd: dr/dx disagrees"},
        PlantedError{"tangent_k_times_ten", "dr/dx disagrees"},
        PlantedError{"tangent_s_dropped", "dr/dx disagrees"},
        // The constraint rows (unknowns 4 and 5 of the four-bar) 1 % too large.
        PlantedError{"tangent_phi_z_one_percent",
                     "dr/dx disagrees with differences of its "
                     "residual in that argument at t = 0 s: row 5, column 3: analytic 202, "
                     "differences 200"},
        // The throttle's d/dp 1 % off: seen at the coarse step, where c_v V/K
        // no longer hides it in the node's row.
        PlantedError{"tangent_throttle_dp",
                     "FAIL  subsystem throttle: analytic tangent against differences of its "
                     "residual: the analytic tangent disagrees with differences of the residual: "
                     "at a step of 0.1 s: row state n1"}),
    [](const ::testing::TestParamInfo<PlantedError>& param) {
      return std::string(param.param.fixture);
    });

// A formulation whose coordinates have no unknown to move them (here: its
// coordinate unknowns declared algebraic) froze the mechanism and exited 0;
// the host refuses it at setup, with the counts.
TEST(PluginCheck, AFormulationThatLeavesTheMechanismWithoutMovingUnknownsIsRefusedAtSetup) {
  const std::string said =
      "formulation 'lagrange-baumgarte-broken' declares 0 second-order and 0 first-order "
      "unknowns for a mechanism of 1 degree of freedom (3 coordinates, constraints of rank 2 "
      "at the start): the coordinates it leaves without one would not move";
  const CliResult check = run_cli("check " + fixture("tangent_no_moving_unknowns") + " " +
                                  mh::test::shipped_model("fourbar.yaml"));
  EXPECT_EQ(check.code, 1) << check.output;
  EXPECT_NE(check.output.find(said), std::string::npos) << check.output;
  const auto model = mh::test::scratch_dir("frozen") / "fourbar.yaml";
  {
    std::ifstream in(mh::test::shipped_model("fourbar.yaml"));
    std::ofstream out(model);
    out << in.rdbuf()
        << "plugins: {lagrange-baumgarte-broken: " << fixture("tangent_no_moving_unknowns")
        << "}\n";
  }
  const CliResult run =
      run_cli("run " + model.string() + " --formulation lagrange-baumgarte-broken --t-end 0.1");
  EXPECT_EQ(run.code, 2) << run.output;
  EXPECT_NE(run.output.find(said), std::string::npos) << run.output;
}

TEST(PluginCheck, AFormulationsOwnBlocksAreComparedAndSaySoWhenTheyPass) {
  const CliResult r =
      run_cli("check " + std::string(mh::test::paths::plugin_dir) + "/monohydra-penalty.so");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok    formulation penalty: its tangent blocks against differences of "
                          "its residual in x, xd, xdd: 3 of 3 columns given"),
            std::string::npos)
      << r.output;
}

TEST(PluginCheck, ARunThatFailsIsReportedAsAFailedRunWithItsTimeNotAsAnException) {
  const CliResult r = run_cli("check " + fixture("failing_evaluate") + " " + spring_model());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: analytic tangent against differences "
                          "of its residual: the run failed: "),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("an exception reached the host"), std::string::npos) << r.output;
}

TEST(HostServices, NullOutPointersNullOrForgedHandlesAndBadLooksAreRefusedWithAMessageNotACrash) {
  // The fixture's setup makes each bad call and fails, naming it, if one is
  // accepted; refused, it goes on as the sound spring and the model runs.
  const auto path = mh::test::scratch_dir("check-model") / "bad-host-calls.yaml";
  write_spring_model_with(path, "bad_host_calls");
  const CliResult r = run_cli("validate " + path.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("accepted a bad call"), std::string::npos) << r.output;
  for (const char* said :
       {"option_number('stiffness'): expected a place for the result, got NULL",
        "option_table('table'): expected a place for the result, got NULL",
        "find_state('spring.x'): expected a place for the result, got NULL",
        "add_point('a'): expected a place for the result, got NULL",
        "the host service option_number with a handle the host did not give it (NULL)",
        "the host service add_state with a handle the host did not give it (forged, or kept past "
        "its instance's destroy)",
        "the host service log with a handle the host did not give it (NULL)",
        "add_visual: expected a spec, got NULL",
        "add_visual: unknown kind 7 (expected MH_VISUAL_ACTUATOR or MH_VISUAL_LINK)",
        "add_visual: no point 2 (this instance added 2 with add_point)",
        "add_visual: point_a and point_b are the same point",
        "add_visual: an actuator needs a positive barrel_length and barrel_diameter (m)",
        "add_visual: no state 99 (expected -1 or a global index below"})
    EXPECT_NE(r.output.find(said), std::string::npos) << said << "\n" << r.output;
}

// Every value a plugin writes is checked where it crosses into the host: a
// NaN output or point-force derivative stops the run at its step, naming the
// instance, its library, the call, what it wrote and the index, and every
// row before it stays.
TEST(HostBoundary, ANonFiniteWriteStopsTheRunNamingTheInstanceItsLibraryTheCallAndTheIndex) {
  const struct {
    const char* fixture;
    const char* said;
  } cases[] = {
      {"nan_output",
       "subsystem 'spring' (faulty-spring) of nan_output.so wrote a non-finite value (nan) in "
       "evaluate: output 'spring.extension' at the accepted step, outputs entry 0"},
      // (the NaN's sign, printed as -nan here, is the plugin's arithmetic's)
      {"nan_force_jacobian", "nan) in point_force_jacobian: dF_dp entry 0"}};
  for (const auto& c : cases) {
    const auto dir = mh::test::scratch_dir(std::string("nonfinite-") + c.fixture);
    const auto model = dir / "spring.yaml";
    write_spring_model_with(model, c.fixture);
    const auto csv = dir / "out.csv";
    const CliResult r = run_cli("run " + model.string() + " --out " + csv.string());
    EXPECT_EQ(r.code, 1) << c.fixture << "\n" << r.output;
    EXPECT_NE(r.output.find("simulation failed at t = 0.5 s, step 500"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(c.said), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(std::string("subsystem 'spring' (faulty-spring) of ") + c.fixture +
                            ".so wrote a non-finite value ("),
              std::string::npos)
        << r.output;
    // The header and the rows of t = 0 to 0.499 s.
    std::ifstream rows(csv);
    long lines = 0;
    for (std::string line; std::getline(rows, line);) ++lines;
    EXPECT_EQ(lines, 501) << c.fixture;
  }
}

// A crash inside a subsystem's evaluate, itself inside the formulation's
// residual: the report names the innermost call in flight.
TEST(HostBoundary, ACrashInsideASubsystemCallNamesTheInstanceTheCallTheTimeAndTheStep) {
  const auto dir = mh::test::scratch_dir("crash-evaluate");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "crash_evaluate");
  const auto csv = dir / "out.csv";
  const CliResult r = run_cli("run " + model.string() + " --out " + csv.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: the run crashed (SIGSEGV) in subsystem 'spring' "
                          "(faulty-spring) of crash_evaluate.so, in its evaluate, at t = 0.501 s, "
                          "step 501; every row up to t = 0.5 s is in '" +
                          csv.string() + "'"),
            std::string::npos)
      << r.output;
}

// Every way a plugin's code can die inside a call ends the run's process,
// not the command: it names the signal, the instance, its library and the
// call, and keeps every row before. A stack overflow too, whose handler
// runs on a stack of its own (crash_report.cpp).
struct CrashKind {
  const char* fixture;
  const char* signal;
};

class HostBoundaryCrash : public ::testing::TestWithParam<CrashKind> {};

TEST_P(HostBoundaryCrash, AnEvaluateThatDiesIsNamedWithTheSignalAndEveryRowBeforeIsKept) {
  const CrashKind kind = GetParam();
  const auto dir = mh::test::scratch_dir(std::string("crash-") + kind.fixture);
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, kind.fixture);
  const auto csv = dir / "out.csv";
  const CliResult r = run_cli("run " + model.string() + " --out " + csv.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find(std::string("monohydra: the run crashed (") + kind.signal +
                          ") in subsystem 'spring' (faulty-spring) of " + kind.fixture +
                          ".so, in its evaluate, at t = 0.501 s, step 501; every row up to t = "
                          "0.5 s is in '" +
                          csv.string() + "'"),
            std::string::npos)
      << r.output;
}

INSTANTIATE_TEST_SUITE_P(Signals, HostBoundaryCrash,
                         ::testing::Values(CrashKind{"abort_evaluate", "SIGABRT"},
                                           CrashKind{"trap_evaluate", "SIGILL"},
                                           CrashKind{"null_write_evaluate", "SIGSEGV"},
                                           CrashKind{"divide_evaluate", "SIGFPE"},
                                           CrashKind{"stack_overflow_evaluate", "SIGSEGV"}),
                         [](const ::testing::TestParamInfo<CrashKind>& p) {
                           return std::string(p.param.fixture);
                         });

// An evaluate that writes one entry past its point forces: the run stops
// at that step naming the instance, its library, the array and the call
// (the entries after the array are the host's guard, not its data), every
// row before kept.
TEST(HostBoundary, AWritePastTheEndOfItsPointForcesStopsTheRunNamingTheArray) {
  const auto dir = mh::test::scratch_dir("overrun-evaluate");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "overrun_evaluate");
  const auto csv = dir / "out.csv";
  const CliResult r = run_cli("run " + model.string() + " --out " + csv.string());
  EXPECT_EQ(r.code, 1) << r.output;
  // Said inside the formulation's residual, whose host service evaluated it.
  EXPECT_NE(r.output.find("monohydra: simulation failed at t = 0.501 s, step 501: residual "
                          "evaluation failed: formulation 'open-loop': residual: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("subsystem 'spring' (faulty-spring) of overrun_evaluate.so wrote past "
                          "the end of its point forces (6 entries) in evaluate\n"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(last_row_time(csv), "0.5");
}

// The same for a derivative array: point_force_jacobian writes one entry
// past dF_dp (two points: 6 x 6 entries) while the step's tangent is made.
TEST(HostBoundary, AWritePastTheEndOfADerivativeArrayStopsTheRunNamingTheArray) {
  const auto dir = mh::test::scratch_dir("overrun-force-jacobian");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "overrun_force_jacobian");
  const CliResult r = run_cli("run " + model.string() + " --out /dev/null");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: simulation failed at t = 0.501 s, step 501: tangent "
                          "assembly failed: formulation 'open-loop': tangent: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("subsystem 'spring' (faulty-spring) of overrun_force_jacobian.so wrote "
                          "past the end of its dF_dp (36 entries) in point_force_jacobian\n"),
            std::string::npos)
      << r.output;
}

// A thread the plugin started crashes later, in its own code, while the
// stepping thread is anywhere: no call of the host's is to blame, and the
// message names the library whose code crashed rather than a call.
TEST(HostBoundary, AThreadAPluginStartedThatCrashesLaterIsBlamedOnItsLibrary) {
  const auto dir = mh::test::scratch_dir("crash-thread");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "thread_crash");
  const auto csv = dir / "out.csv";
  const CliResult r = run_cli("run " + model.string() + " --out " + csv.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: the run crashed (SIGSEGV) in the code of thread_crash.so, "
                          "outside the plugin calls the host marks (a thread it started); every "
                          "row up to t = "),
            std::string::npos)
      << r.output;
}

// A crash while the run is set up: the child that sets the run up and steps
// it dies, and the command itself reports the call and exits 1.
TEST(HostBoundary, ACrashInSetupEndsTheRunsChildAndTheCommandNamesTheInstanceAndTheCall) {
  const auto model = mh::test::scratch_dir("crash-setup") / "spring.yaml";
  write_spring_model_with(model, "crash_setup");
  const CliResult r = run_cli("run " + model.string() + " --out /dev/null");
  EXPECT_EQ(r.code, 1) << r.output;  // an exit, not the command dying of the signal
  EXPECT_NE(r.output.find("monohydra: the run crashed (SIGSEGV) in subsystem 'spring' "
                          "(faulty-spring) of crash_setup.so, in its setup"),
            std::string::npos)
      << r.output;
}

// A formulation's start and accept write x, xd, xdd that the integrator's
// history takes: a NaN there is named with its writer, the call and the
// entry, and every row before stays.
TEST(HostBoundary, NanInAFormulationsStartOrAcceptIsNamedWithTheCallAndTheEntry) {
  for (const auto& [name, message, last_row] :
       {std::tuple<std::string, std::string, std::string>{
            "nan_start",
            "simulation failed at t = 0 s, step 0: formulation 'nan-formulation' of "
            "nan_start.so wrote a non-finite value (nan) in start: x entry 0",
            ""},
        std::tuple<std::string, std::string, std::string>{
            "nan_accept",
            "simulation failed at t = 0.006 s, step 6: formulation 'nan-formulation' of "
            "nan_accept.so wrote a non-finite value (nan) in accept: xd entry 0",
            "0.005"}}) {
    const auto dir = mh::test::scratch_dir("nan-formulation-" + name);
    const auto model = dir / "pendulum.yaml";
    {
      std::ifstream in(mh::test::shipped_model("double-pendulum.yaml"));
      std::ofstream out(model);
      out << in.rdbuf() << "plugins: {nan-formulation: " << fixture(name) << "}\n";
    }
    const auto csv = dir / "out.csv";
    const CliResult r =
        run_cli("run " + model.string() + " --formulation nan-formulation --t-end 0.02 --out " +
                csv.string());
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    if (last_row.empty()) continue;
    EXPECT_EQ(last_row_time(csv), last_row);
  }
}

// destroy is a plugin call like the others: a crash in it is named.
TEST(HostBoundary, ACrashInDestroyIsNamedWithTheInstanceAndTheCall) {
  const auto model = mh::test::scratch_dir("crash-destroy") / "spring.yaml";
  write_spring_model_with(model, "crash_destroy");
  const CliResult r = run_cli("validate " + model.string());  // sets up and destroys here
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("monohydra: crashed (SIGSEGV) in subsystem 'spring' (faulty-spring) of "
                          "crash_destroy.so, in its destroy"),
            std::string::npos)
      << r.output;
}

// A plugin call that never returns: the host's watchdog stops the command
// once the call has been in flight for --call-timeout, naming it.
TEST(HostBoundary, ACreateThatNeverReturnsIsStoppedNamingTheInstanceAndTheCall) {
  const auto model = mh::test::scratch_dir("hang-create") / "spring.yaml";
  write_spring_model_with(model, "hang_create");
  const CliResult r = run_cli("run " + model.string() + " --out /dev/null --call-timeout 0.5");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: subsystem 'spring' (faulty-spring) of hang_create.so has "
                          "not returned from its create within 0.5 s"),
            std::string::npos)
      << r.output;
}

// The same in the child that steps: every row before the hung call stays.
TEST(HostBoundary, AnEvaluateThatNeverReturnsStopsTheRunKeepingEveryRowBefore) {
  const auto dir = mh::test::scratch_dir("hang-evaluate");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "hang_evaluate");
  const auto csv = dir / "out.csv";
  const CliResult r =
      run_cli("run " + model.string() + " --out " + csv.string() + " --call-timeout 0.5");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: subsystem 'spring' (faulty-spring) of hang_evaluate.so has "
                          "not returned from its evaluate within 0.5 s (at t = 0.501 s, step 501)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(last_row_time(csv), "0.5");
}

// Without --call-timeout a call inside a step has 5 s, not a minute: the
// hung evaluate is named within seconds, and the message says how to raise
// the limit for a slow honest plugin.
TEST(HostBoundary, AnEvaluateThatNeverReturnsIsStoppedWithinTheStepCallsDefaultOfFiveSeconds) {
  const auto dir = mh::test::scratch_dir("hang-evaluate-default");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "hang_evaluate");
  const auto began = std::chrono::steady_clock::now();
  const CliResult r = run_cli("run " + model.string() + " --out /dev/null");
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("monohydra: subsystem 'spring' (faulty-spring) of hang_evaluate.so has "
                          "not returned from its evaluate within 5 s (at t = 0.501 s, step 501): "
                          "stopped (--call-timeout S raises the limit)"),
            std::string::npos)
      << r.output;
  EXPECT_LT(took, 15.0);
}

// SIGTERM while a plugin call never returns: the run cannot reach its next
// row to stop there, and does not wait for the call's 5 s either: it stops
// within a second, naming the call, with SIGTERM's exit status, every row
// before it kept.
TEST(HostBoundary, SigtermDuringACallThatNeverReturnsStopsTheRunWithinASecond) {
  const auto dir = mh::test::scratch_dir("hang-evaluate-sigterm");
  const auto model = dir / "spring.yaml";
  write_spring_model_with(model, "hang_evaluate");
  const auto csv = dir / "out.csv";
  // Signalled once the row at t = 0.5 s is written (the header and 501 rows)
  // and the evaluate of step 501 has hung for 0.3 s; the time from the
  // signal to the command's end printed last.
  const CliResult r =
      run_shell("( MONOHYDRA_PLUGIN_PATH= " + std::string(mh::test::paths::executable) + " run " +
                model.string() + " --out " + csv.string() +
                " & p=$!; for i in $(seq 400); do [ \"$(wc -l < " + csv.string() +
                " 2>/dev/null)\" -ge 502 ] && break; sleep 0.05; done; sleep 0.3; " +
                "t0=$(date +%s.%N); kill -TERM $p; wait $p; rc=$?; t1=$(date +%s.%N); " +
                "echo; echo \"took $(awk -v a=$t0 -v b=$t1 'BEGIN { print b - a }')\"; exit $rc )");
  EXPECT_EQ(r.code, 143) << r.output;
  EXPECT_NE(
      r.output.find("monohydra: interrupted by SIGTERM: subsystem 'spring' (faulty-spring) of "
                    "hang_evaluate.so had not returned from its evaluate (at t = 0.501 s, "
                    "step 501): stopped there"),
      std::string::npos)
      << r.output;
  const size_t at = r.output.rfind("took ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_LT(std::stod(r.output.substr(at + 5)), 1.0) << r.output;
  EXPECT_EQ(last_row_time(csv), "0.5");
}

TEST(HostBoundary, ACallTimeoutThatIsNotATimeIsRefusedNamingTheFlagAndTheValue) {
  const CliResult word = run_cli("run " + spring_model() + " --call-timeout soon");
  EXPECT_EQ(word.code, 2) << word.output;
  EXPECT_NE(word.output.find("monohydra: --call-timeout expects a number, got 'soon'"),
            std::string::npos)
      << word.output;
  const CliResult negative = run_cli("run " + spring_model() + " --call-timeout -1");
  EXPECT_EQ(negative.code, 2) << negative.output;
  EXPECT_NE(
      negative.output.find("monohydra: --call-timeout expects a time in s (0 or more), got '-1'"),
      std::string::npos)
      << negative.output;
}

TEST(PluginCheck, AFailingCreateFailsWithThePluginsReason) {
  const CliResult r = run_cli("check " + fixture("failing_create") + " " + spring_model());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: create/setup/destroy x3"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("create fails on purpose"), std::string::npos) << r.output;
}

TEST(PluginCheck, AMissingFunctionFailsNamingIt) {
  const CliResult r = run_cli("check " + fixture("missing_evaluate") + " " + spring_model());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: create/setup/destroy x3"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("evaluate"), std::string::npos) << r.output;
}

TEST(PluginCheck, AnExceptionThrownAcrossTheCBoundaryFailsAndTheHostSurvives) {
  const CliResult r = run_cli("check " + fixture("throwing") + " " + spring_model());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: create/setup/destroy x3"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("monohydra check: FAILED"), std::string::npos) << r.output;
}

TEST(PluginCheck, AWrongAbiVersionFailsAtLoadSayingWhichVersions) {
  const CliResult r =
      run_cli("check " + std::string(mh::test::paths::fixture_dir) + "/mh_fixture_major_one.so");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  load: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("was built for monohydra ABI 1."), std::string::npos) << r.output;
}

TEST(PluginCheck, ALibraryWithoutTheEntrySymbolFailsAtLoad) {
  const CliResult r =
      run_cli("check " + std::string(mh::test::paths::fixture_dir) + "/mh_fixture_not_a_plugin.so");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  load: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("mh_entry"), std::string::npos) << r.output;
}

// --at moves the blocks' comparison to the times given (the steps nearest
// them); a negative time or a word is refused with exit 2, naming it.
TEST(PluginCheck, AtComparesTheBlocksAtTheTimesGivenAndRefusesATimeBeforeTheStart) {
  const std::string library = std::string(mh::test::paths::plugin_dir) + "/monohydra-hydraulics.so";
  CliResult r = run_cli("check " + library + " --at 0.1,0.5");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(
      r.output.find("ok    subsystem throttle: its derivative blocks against differences "
                    "of its evaluate: 16 entry comparisons of 1 instance(s) at t = 0.1, 0.5 s"),
      std::string::npos)
      << r.output;
  for (const char* bad : {"-1", "soon"}) {
    r = run_cli("check " + library + " --at 0.1," + bad);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(std::string("a time in s at or after the run's start (0), not '") +
                            bad + "'"),
              std::string::npos)
        << r.output;
  }
}

TEST(PluginCheck, BadArgumentsExitTwoWithTheUsage) {
  const CliResult r = run_cli("check");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("usage: monohydra check PLUGIN.so [MODEL.yaml]"), std::string::npos)
      << r.output;
}

// Without a model, each subsystem is checked on the example model
// its factory declares; a broken one fails naming it; one without is skipped.
TEST(PluginCheck, EveryShippedSubsystemIsCheckedOnItsDeclaredExampleModel) {
  for (const char* library :
       {"monohydra-hydraulics", "monohydra-mechanics", "monohydra-earthmoving"}) {
    const CliResult r =
        run_cli("check " + std::string(mh::test::paths::plugin_dir) + "/" + library + ".so");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("skip"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(declared by " + std::string(library) + ".so), 20 steps"),
              std::string::npos)
        << r.output;
  }
}

TEST(PluginCheck, ABrokenDeclaredExampleModelFailsNamingItsFieldAndLine) {
  const CliResult r = run_cli("check " + fixture("example_broken"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  subsystem faulty-spring: declared example model: the example "
                          "model of subsystem 'faulty-spring' (declared by example_broken.so)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("hinge"), std::string::npos) << r.output;
}

TEST(PluginCheck, ASubsystemThatDeclaresNoExampleModelIsSkippedWithTheReason) {
  const CliResult r = run_cli("check " + fixture("short_factory_spring"));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok    load: ABI 3." + std::to_string(MH_ABI_VERSION_MINOR) + ".0"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("skip  subsystem faulty-spring: no shipped model uses it and it "
                          "declares no example model"),
            std::string::npos)
      << r.output;
}

}  // namespace
