// The commands that run plugin code in their own process under the one
// supervisor (hosts/monohydra/supervised.cpp): a plugin that dies inside a
// call ends the child, and the command names the signal, the instance, its
// library and the call, and exits 1; it is never itself killed by the signal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hosts/cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using mh::test::CliResult;
using mh::test::run_cli;

// tests/fixtures/check/spring-pendulum.yaml with its spring from `fixture`
// (tests/fixtures/faulty/faulty_spring.c).
fs::path spring_model_with(const std::string& fixture) {
  const fs::path dir = mh::test::scratch_dir("supervised-" + fixture);
  const fs::path model = dir / "spring.yaml";
  std::ifstream in(std::string(mh::test::paths::source_dir) +
                   "/tests/fixtures/check/spring-pendulum.yaml");
  std::ofstream out(model);
  out << in.rdbuf() << "plugins: {faulty-spring: " << mh::test::paths::check_fixture_dir << "/"
      << fixture << ".so}\n";
  return model;
}

struct Case {
  const char* name;     // the test's
  const char* fixture;  // the spring's fault
  const char* command;  // the command and its options; MODEL stands for the model
  const char* crash;    // what the command must say
};

class SupervisedCommand : public ::testing::TestWithParam<Case> {};

TEST_P(SupervisedCommand, APluginThatDiesInACallIsNamedAndTheCommandExitsOne) {
  const Case c = GetParam();
  const fs::path model = spring_model_with(c.fixture);
  const fs::path dir = model.parent_path();
  {
    std::ofstream data(dir / "data.csv");
    data << "t,z1\n0,0\n0.1,0\n0.6,0\n";  // fit runs to its last sample
  }
  std::string command = c.command;
  command.replace(command.find("MODEL"), 5, model.string());
  for (size_t at; (at = command.find("DIR")) != std::string::npos;)
    command.replace(at, 3, dir.string());
  const CliResult r = run_cli(command);
  EXPECT_EQ(r.code, 1) << command << "\n" << r.output;  // -1: killed by a signal
  EXPECT_NE(r.output.find(c.crash), std::string::npos) << command << "\n" << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    Commands, SupervisedCommand,
    ::testing::Values(
        Case{
            "validate", "crash_setup", "validate MODEL",
            "monohydra: crashed (SIGSEGV) in subsystem 'spring' (faulty-spring) of crash_setup.so, "
            "in its setup, at t = 0 s, step 0"},
        Case{"linearize", "abort_evaluate", "linearize MODEL --at 0.7",
             "monohydra: crashed (SIGABRT) in subsystem 'spring' (faulty-spring) of "
             "abort_evaluate.so, in its evaluate, at t = 0.501 s, step 501"},
        Case{"sensitivities", "stack_overflow_evaluate",
             "sensitivities MODEL --params bodies/link/mass --out DIR/s.csv",
             "monohydra: crashed (SIGSEGV) in subsystem 'spring' (faulty-spring) of "
             "stack_overflow_evaluate.so, in its evaluate, at t = 0.501 s, step 501"},
        Case{"fit", "divide_evaluate",
             "fit MODEL --data DIR/data.csv --params bodies/link/mass --t-end 0.6",
             "monohydra: crashed (SIGFPE) in subsystem 'spring' (faulty-spring) of "
             "divide_evaluate.so, in its evaluate, at t = 0.501 s, step 501"},
        Case{
            "fmu", "crash_setup", "fmu MODEL --out DIR/spring.fmu",
            "monohydra: crashed (SIGSEGV) in subsystem 'spring' (faulty-spring) of crash_setup.so, "
            "in its setup, at t = 0 s, step 0"}),
    [](const ::testing::TestParamInfo<Case>& p) { return std::string(p.param.name); });

}  // namespace
