// The sparsity service (sdk sparsity.h, core/src/plugins/host_services.cpp
// and the tangent's pattern in core/src/step/tangent.cpp): a declared block
// enters the tangent with its entries only and gives the same solution; a
// jacobian that writes outside its declaration stops the run naming the
// entry; a declaration of a state the instance does not touch fails setup.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "build_paths.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

const char* kModel = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pair, type: exchange-pair, rate: 3.0}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

std::string fixture(const std::string& variant) {
  return std::string(mh::test::paths::sparsity_plugin_dir) + "/exchange_pair_" + variant + ".so";
}

TEST(SparsityService, ADeclaredBlockEntersTheTangentWithItsEntriesAndSolvesTheExchange) {
  const ModelFile file = parse_model_text(kModel, "pair.yaml");
  Simulation sim(file, build_plugins_with(fixture("sound")));
  sim.start();
  // The slider's coordinate, and the pair's two states with their four
  // entries: the diagonal and the two declared.
  EXPECT_EQ(sim.tangent_nonzeros(), 1 + 4);
  for (int k = 0; k < 1000; ++k) sim.step();
  const double x1 = sim.states()[sim.state_index("pair.x1")];
  const double x2 = sim.states()[sim.state_index("pair.x2")];
  EXPECT_NEAR(x1 + x2, 1.0, 1e-12);
  // x1 - x2 decays as exp(-2 k t); the trapezoidal rule takes it, exactly,
  // by (1 - k h) / (1 + k h) a step (2 k h = 0.006): 1.8e-5 short of the
  // exponential after 1 s.
  EXPECT_NEAR(x1 - x2, std::pow((1.0 - 0.003) / (1.0 + 0.003), 1000), 1e-13);
  EXPECT_NEAR(x1 - x2, std::exp(-6.0), 2e-5 * std::exp(-6.0));
}

TEST(SparsityService, AJacobianWritingOutsideItsDeclarationStopsTheRunNamingTheEntry) {
  const ModelFile file = parse_model_text(kModel, "pair.yaml");
  Simulation sim(file, build_plugins_with(fixture("undeclared_write")));
  try {
    sim.start();
    sim.step();
    FAIL() << "the run went on";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("subsystem 'pair'"), std::string::npos) << what;
    EXPECT_NE(what.find("outside the entries it declared"), std::string::npos) << what;
    EXPECT_NE(what.find("row pair.x2, column pair.x1"), std::string::npos) << what;
  }
}

TEST(SparsityService, DeclaringAStateTheInstanceDoesNotTouchFailsItsSetupSayingSo) {
  const ModelFile file = parse_model_text(kModel, "pair.yaml");
  std::string log;
  try {
    Simulation sim(file, build_plugins_with(fixture("untouched")), RunChoices{},
                   [&](mh_log_level, const std::string& source, const std::string& line) {
                     log += source + ": " + line + "\n";
                   });
    FAIL() << "setup passed";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("pair"), std::string::npos) << e.what();
  }
  EXPECT_NE(log.find("declare_entries: entry 0 names state"), std::string::npos) << log;
  EXPECT_NE(log.find("does not touch"), std::string::npos) << log;
}

}  // namespace
}  // namespace mh::test
