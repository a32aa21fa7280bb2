// A Simulation whose construction throws half-way destroys every plugin
// instance it had already created (core/src/plugins/plugin_instance.hpp): the first
// subsystem is set up, the second refuses its options. In the sanitizer
// build (.ci/sanitize) LeakSanitizer checks at exit that nothing the plugins
// allocated is left; everywhere, the error names the second subsystem and a
// model that sets up still does after repeated failures.
#include <gtest/gtest.h>

#include <string>

#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const std::string kHead = R"(units: {length: m, mass: kg, time: s, angle: deg}
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},
     mass: 10, shape: {type: beam, length: 1}, z0: 0}
subsystems:
  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 1e7}
)";
const std::string kHose =
    "  - {name: hose, type: volume, ports: {p: n1}, volume: 1e-4, bulk_modulus: 5e8,\n"
    "     fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}\n";
const std::string kOrifice =
    "  - {name: orifice, type: throttle, ports: {a: supply, b: n1}, area: 1e-5,\n"
    "     discharge_coefficient: 0.7, density: 850}\n";

std::string with_hose(const std::string& from, const std::string& to) {
  std::string hose = kHose;
  hose.replace(hose.find(from), from.size(), to);
  return kHead + hose + kOrifice;
}

// The InputError the model's setup raises ("" when it sets up).
std::string setup_error(const std::string& text) {
  const ModelFile file = parse_model_text(text, "circuit.yaml");
  try {
    Simulation sim(file, test::build_plugins());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(SimulationSetupFailure, ABadOptionOfTheSecondSubsystemLeavesNoInstanceBehind) {
  ASSERT_EQ(setup_error(kHead + kHose + kOrifice), "");
  struct Case {
    std::string from, to, key;
  };
  const Case cases[] = {
      {"volume: 1e-4", "volume: -1e-4", "volume"},              // refused by the plugin's setup
      {"volume: 1e-4", "volume: lots", "volume"},               // not a number
      {"volume: 1e-4", "volume: 1e-4, colour: red", "colour"},  // unknown to the plugin
  };
  for (int round = 0; round < 3; ++round) {
    for (const auto& c : cases) {
      const std::string err = setup_error(with_hose(c.from, c.to));
      EXPECT_TRUE(has(err, "circuit.yaml:")) << err;
      EXPECT_TRUE(has(err, "subsystem 'hose'")) << err;
      EXPECT_TRUE(has(err, "'" + c.key + "'")) << err;
    }
  }
  // The plugins are still usable after the failures.
  EXPECT_EQ(setup_error(kHead + kHose + kOrifice), "");
}

TEST(SimulationSetupFailure, AnUnknownIntegratorOptionLeavesNoInstanceBehind) {
  // The subsystems and the formulation are set up when the integrator refuses.
  const std::string err =
      setup_error(kHead + kHose + kOrifice + "integrator: {name: trapezoidal, colour: red}\n");
  EXPECT_TRUE(has(err, "integrator 'trapezoidal'")) << err;
  EXPECT_TRUE(has(err, "'colour'")) << err;
}

}  // namespace
}  // namespace mh
