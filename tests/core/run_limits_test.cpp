// A run's settings are checked before it starts: each refusal names where the
// setting was written, the numbers, the accepted range and the flag.
#include "monohydra/core/run_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A pendulum whose solver block is line 8; `solver` is written there.
std::string pendulum(const std::string& solver) {
  return "units: {length: m, mass: kg, time: s, angle: rad}\n"  // 1
         "bodies:\n"                                            // 2
         "  - name: rod\n"                                      // 3
         "    parent: ground\n"                                 // 4
         "    joint: {type: revolute, axis: [0, 0, 1]}\n"       // 5
         "    mass: 1\n"                                        // 6
         "    shape: {type: beam, length: 1}\n"                 // 7
         + solver;                                              // 8
}

// The InputError check_run_settings throws for `file` with `settings`.
InputError refusal(const ModelFile& file, const SolverSettings& settings, std::size_t columns = 0,
                   SettingOrigins origins = {}, RunLimits limits = {}) {
  try {
    check_run_settings(file, settings, limits, columns, origins);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return InputError({}, "", "");
}

InputError refusal_of(const std::string& solver, std::size_t columns = 0) {
  const ModelFile file = parse_model_text(pendulum(solver), "p.yaml");
  return refusal(file, file.solver, columns);
}

TEST(RunLimits, StepCountAboveTheLimitIsRefusedWithBothNumbersAndTheFlag) {
  const InputError e = refusal_of("solver: {dt: 0.001, t_end: 1e300}\n");
  EXPECT_EQ(std::string(e.what()),
            "p.yaml:8:28: solver.t_end: t_end / dt = 1e+300 / 0.001 = 1e+303 steps, above the "
            "limit of 1e+08 steps (raise it with --max-steps N)");
}

TEST(RunLimits, EndTimeBeyondALongFromTheCommandLineIsRefusedNotWrapped) {
  const ModelFile file = parse_model_text(pendulum("solver: {dt: 0.001, t_end: 1}\n"), "p.yaml");
  SolverSettings s = file.solver;
  s.t_end = 1e19;  // 1e22 steps: lround overflowed to zero steps before
  const InputError e = refusal(file, s, 0, SettingOrigins{false, true});
  EXPECT_EQ(std::string(e.what()),
            "command line: --t-end: t_end / dt = 1e+19 / 0.001 = 1e+22 steps, above the limit of "
            "1e+08 steps (raise it with --max-steps N)");
}

TEST(RunLimits, InfiniteEndTimeIsRefused) {
  const ModelFile file = parse_model_text(pendulum("solver: {dt: 0.001, t_end: 1}\n"), "p.yaml");
  SolverSettings s = file.solver;
  s.t_end = std::numeric_limits<double>::infinity();
  const InputError e = refusal(file, s, 0, SettingOrigins{false, true});
  EXPECT_EQ(std::string(e.what()),
            "command line: --t-end: expected a positive finite end time in s (a run of zero steps "
            "is an error), got inf");
}

TEST(RunLimits, ZeroStepRunIsAnError) {
  const InputError e = refusal_of("solver: {dt: 0.001, t_end: 0}\n");
  EXPECT_EQ(e.mark().line, 8);
  EXPECT_EQ(e.field(), "solver.t_end");
  EXPECT_NE(std::string(e.what()).find("a run of zero steps is an error), got 0"),
            std::string::npos)
      << e.what();
}

TEST(RunLimits, SubnormalTimeStepIsRefusedWithTheAcceptedRange) {
  const ModelFile file = parse_model_text(pendulum("solver: {dt: 0.001, t_end: 1}\n"), "p.yaml");
  SolverSettings s = file.solver;
  s.dt = 5e-324;
  const InputError e = refusal(file, s);
  EXPECT_EQ(std::string(e.what()),
            "p.yaml:8:14: solver.dt: expected a time step from 1e-09 s to t_end = 1 s, got "
            "4.94066e-324");
}

TEST(RunLimits, TimeStepBelowOneNanosecondIsRefused) {
  const InputError e = refusal_of("solver: {dt: 1e-12, t_end: 1}\n");
  EXPECT_EQ(std::string(e.what()),
            "p.yaml:8:14: solver.dt: expected a time step from 1e-09 s to t_end = 1 s, got 1e-12");
}

TEST(RunLimits, TimeStepAboveTheEndTimeIsRefused) {
  const InputError e = refusal_of("solver: {dt: 2, t_end: 1}\n");
  EXPECT_EQ(e.field(), "solver.dt");
  EXPECT_NE(std::string(e.what()).find("to t_end = 1 s, got 2"), std::string::npos) << e.what();
}

TEST(RunLimits, OutputAboveTheLimitIsRefusedWithTheEstimate) {
  const InputError e = refusal_of("solver: {dt: 0.001, t_end: 1e5}\n", 9);
  EXPECT_EQ(std::string(e.what()),
            "p.yaml:8:28: solver.t_end: the CSV would take about 1.8e+10 bytes (1e+08 rows x 9 "
            "columns x ~20 bytes), above the limit of 1e+10 bytes (raise it with "
            "--max-output-bytes N)");
}

TEST(RunLimits, RaisedLimitsLetALongRunThrough) {
  const ModelFile file = parse_model_text(pendulum("solver: {dt: 0.001, t_end: 1e5}\n"), "p.yaml");
  RunLimits limits;
  limits.max_steps = 1e9;
  limits.max_output_bytes = 1e11;
  EXPECT_EQ(check_run_settings(file, file.solver, limits, 9), 100000000L);
}

TEST(RunLimits, ModelWithoutSolverBlockIsRefusedAsPossiblyCutShort) {
  const ModelFile file = parse_model_text(pendulum(""), "p.yaml");
  const InputError e = refusal(file, file.solver);
  EXPECT_EQ(e.field(), "solver.dt");
  EXPECT_NE(std::string(e.what()).find("so a file without one may have been cut short"),
            std::string::npos)
      << e.what();
  // Both given on the command line: the model is complete as far as a run goes.
  EXPECT_EQ(check_run_settings(file, file.solver, {}, 0, SettingOrigins{true, true}), 10000L);
}

// Every shipped model cut after any of its lines is refused before it runs
// (it never runs as a smaller model); the whole file passes.
TEST(RunLimits, EveryLinePrefixOfAShippedModelIsRefused) {
  for (const char* name : {"fourbar.yaml", "quickreturn.yaml", "crank-rocker.yaml",
                           "double-pendulum.yaml", "maxwell-pendulum.yaml"}) {
    std::ifstream in(test::source_path("models/") + name);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    int prefixes = 0;
    for (size_t cut = text.find('\n'); cut + 1 < text.size(); cut = text.find('\n', cut + 1)) {
      ++prefixes;
      bool refused = false;
      try {
        const ModelFile file = parse_model_text(text.substr(0, cut + 1), name);
        check_run_settings(file, file.solver, {}, 0);
      } catch (const InputError&) {
        refused = true;
      }
      EXPECT_TRUE(refused) << name << " cut after byte " << cut + 1;
    }
    EXPECT_GT(prefixes, 20) << name;
    const ModelFile whole = parse_model_text(text, name);
    EXPECT_GT(check_run_settings(whole, whole.solver, {}, 0), 0) << name;
  }
}

TEST(RunLimits, PlannedStepsNeverOverflow) {
  SolverSettings s;
  s.dt = 1e-300;
  s.t_end = 1e300;
  EXPECT_EQ(planned_steps(s), -1);
  s.t_end = 0.0;
  EXPECT_EQ(planned_steps(s), -1);
  s.t_end = std::nan("");
  EXPECT_EQ(planned_steps(s), -1);
  s.dt = 0.001;
  s.t_end = 0.25;
  EXPECT_EQ(planned_steps(s), 250);
}

TEST(RunLimits, UnknownStateKeyIsRefusedWithItsLine) {
  const ModelFile file = parse_model_text(
      pendulum("subsystems:\n"        // 8
               "  - name: m\n"        // 9
               "    type: maxwell\n"  // 10
               "    points: {a: {body: ground, at: [0, 0, 0]}, b: {body: rod, at: [1, 0, 0]}}\n"
               "    stiffness: 100\n"       // 12
               "    damping: 10\n"          // 13
               "    free_length: 1\n"       // 14
               "    states: {nosuch: x}\n"  // 15
               "solver: {dt: 0.001, t_end: 1}\n"),
      "p.yaml");
  const Simulation sim(file, test::build_plugins());
  try {
    check_column_names(file, sim);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "p.yaml:15:14: subsystems[0].states.nosuch: unknown state 'nosuch' (the maxwell 'm' "
              "declares no such state)");
  }
}

}  // namespace
}  // namespace mh
