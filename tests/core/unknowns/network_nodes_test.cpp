// Circuits are graphs in the model file: the host joins ports into nodes and
// refuses a bad circuit with the file, line, component and port.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// An arm on a pin, a pump feeding a hose through an orifice.
const std::string kHead = R"(units: {length: m, mass: kg, time: s, angle: deg}
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},
     mass: 10, shape: {type: beam, length: 1}, z0: 0}
)";
const std::string kPump =
    "  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 1e7}\n";
const std::string kHose =
    "  - {name: hose, type: volume, ports: {p: n1}, volume: 1e-4, bulk_modulus: 5e8,\n"
    "     fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}\n";
const std::string kOrifice =
    "  - {name: orifice, type: throttle, ports: {a: supply, b: n1}, area: 1e-5,\n"
    "     discharge_coefficient: 0.7, density: 850}\n";

std::string model(const std::string& subsystems) {
  return kHead + "subsystems:\n" + subsystems;
}

// The InputError a model's setup raises ("" when it sets up).
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

TEST(NetworkNodes, PortsNamingOneNodeShareOneEffortState) {
  const ModelFile file = parse_model_text(model(kPump + kHose + kOrifice), "circuit.yaml");
  Simulation sim(file, test::build_plugins());
  // Two nodes (supply, n1) and the pump's flow; columns named after the nodes.
  EXPECT_GE(sim.state_index("supply"), 0);
  EXPECT_GE(sim.state_index("n1"), 0);
  sim.start();
  EXPECT_DOUBLE_EQ(sim.states()[sim.state_index("supply")], 1e7);
  EXPECT_DOUBLE_EQ(sim.states()[sim.state_index("n1")], 1e5);
  // The hose fills through the orifice: C pdot = Cv sqrt(ps - p) with
  // u = sqrt(ps - p) gives u(t) = u0 - Cv t / (2 C), in closed form while the
  // drop stays above the laminar 2 bar; the pump delivers what the orifice passes.
  const double C = 1e-4 * (1.0 / 5e8 + 1.0 / 1.5e9);
  const double Cv = 0.7 * 1e-5 * std::sqrt(2.0 / 850.0);
  const double ps = 1e7, u0 = std::sqrt(ps - 1e5);
  RunChoices fine;
  fine.dt = 1e-5;
  Simulation sim_fine(file, test::build_plugins(), fine);
  sim_fine.start();
  for (int k = 0; k < 200; ++k) sim_fine.step();
  const double u = u0 - Cv * 2e-3 / (2.0 * C);
  const double p_exact = ps - u * u;  // 6.49 MPa at 2 ms
  const double p1 = sim_fine.states()[sim_fine.state_index("n1")];
  EXPECT_NEAR(p1, p_exact, 1e-4 * ps);
  EXPECT_DOUBLE_EQ(sim_fine.states()[sim_fine.state_index("supply")], ps);
  EXPECT_NEAR(sim_fine.states()[sim_fine.state_index("pump.q")], Cv * std::sqrt(ps - p1),
              1e-6 * Cv * u0);
}

TEST(NetworkNodes, AnUnconnectedPortIsRefusedNamingTheComponentAndPort) {
  std::string orifice = kOrifice;
  orifice.replace(orifice.find(", b: n1"), 7, "");
  const std::string err = setup_error(model(kPump + kHose + orifice));
  EXPECT_TRUE(has(err, "circuit.yaml:")) << err;
  EXPECT_TRUE(has(err, "subsystem 'orifice'")) << err;
  EXPECT_TRUE(has(err, "port 'b'")) << err;
  EXPECT_TRUE(has(err, "not connected")) << err;
}

TEST(NetworkNodes, TwoSourcesOnOneNodeAreRefusedAsTwoOutputs) {
  const std::string pump2 =
      "  - {name: pump2, type: pressure-source, ports: {p: supply}, pressure: 2e7}\n";
  const std::string err = setup_error(model(kPump + pump2 + kHose + kOrifice));
  EXPECT_TRUE(has(err, "circuit.yaml:")) << err;
  EXPECT_TRUE(has(err, "subsystem 'pump2'")) << err;
  EXPECT_TRUE(has(err, "subsystem 'pump' port 'p'")) << err;
  EXPECT_TRUE(has(err, "two outputs")) << err;
}

TEST(NetworkNodes, ADeadEndNodeIsRefusedAsAPortLeftUnconnected) {
  std::string hose = kHose;
  hose.replace(hose.find("p: n1"), 5, "p: n9");
  const std::string err = setup_error(model(kPump + hose + kOrifice));
  EXPECT_TRUE(has(err, "circuit.yaml:")) << err;
  EXPECT_TRUE(has(err, "port left unconnected")) << err;
  EXPECT_TRUE(has(err, "node 'n9'") || has(err, "node 'n1'")) << err;
}

TEST(NetworkNodes, APortTheComponentLacksIsRefused) {
  std::string orifice = kOrifice;
  orifice.replace(orifice.find("b: n1"), 5, "b: n1, c: n1");
  const std::string err = setup_error(model(kPump + kHose + orifice));
  EXPECT_TRUE(has(err, "circuit.yaml:3") || has(err, "circuit.yaml:")) << err;
  EXPECT_TRUE(has(err, "port 'c'")) << err;
  EXPECT_TRUE(has(err, "unknown port")) << err;
}

TEST(NetworkNodes, ANegativeVolumeOrBulkModulusIsRefusedOnItsLine) {
  for (const auto& [from, to, key] :
       {std::make_tuple("volume: 1e-4", "volume: -1e-4", "volume"),
        std::make_tuple("bulk_modulus: 5e8", "bulk_modulus: -5e8", "bulk_modulus"),
        std::make_tuple("fluid_bulk_modulus: 1.5e9", "fluid_bulk_modulus: 0",
                        "fluid_bulk_modulus")}) {
    std::string hose = kHose;
    hose.replace(hose.find(from), std::string(from).size(), to);
    const std::string err = setup_error(model(kPump + hose + kOrifice));
    // The hose's options are on lines 7 and 8 of the text.
    EXPECT_TRUE(has(err, "circuit.yaml:7:") || has(err, "circuit.yaml:8:")) << err;
    EXPECT_TRUE(has(err, "subsystem 'hose'")) << err;
    EXPECT_TRUE(has(err, std::string("'") + key + "'")) << err;
  }
}

// A cylinder from the ground below the pin to the arm's tip, its chambers
// vented to a tank through wide orifices: the arm falls under gravity and the
// rod bottoms out.
std::string falling_arm(double length) {
  return model(
      "  - {name: tank, type: pressure-source, ports: {p: T}, pressure: 1e5}\n"
      "  - {name: hA, type: volume, ports: {p: nA}, volume: 1e-5, bulk_modulus: 5e8,\n"
      "     fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}\n"
      "  - {name: hB, type: volume, ports: {p: nB}, volume: 1e-5, bulk_modulus: 5e8,\n"
      "     fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}\n"
      "  - {name: vA, type: throttle, ports: {a: nA, b: T}, area: 1e-3,\n"
      "     discharge_coefficient: 0.7, density: 850}\n"
      "  - {name: vB, type: throttle, ports: {a: nB, b: T}, area: 1e-3,\n"
      "     discharge_coefficient: 0.7, density: 850}\n"
      "  - name: cyl\n"
      "    type: cylinder\n"
      "    points: {a: {body: ground, at: [0, -1, 0]}, b: {body: arm, at: [1, 0, 0]}}\n"
      "    ports: {A: nA, B: nB}\n"
      "    piston_diameter: 0.02\n"
      "    rod_diameter: 0.01\n"
      "    length: " +
      std::to_string(length) +
      "\n"
      "    chamber_bulk_modulus: 3e10\n"
      "    fluid_bulk_modulus: 1.5e9\n"
      "    efficiency: 0.9\n");
}

TEST(NetworkNodes, ACylinderTooLongForItsInitialLengthIsRefused) {
  // s0 = sqrt(2) m: a 2 m cylinder would need a negative piston-side chamber.
  const std::string err = setup_error(falling_arm(2.0));
  EXPECT_TRUE(has(err, "circuit.yaml:")) << err;
  EXPECT_TRUE(has(err, "subsystem 'cyl'")) << err;
  EXPECT_TRUE(has(err, "'length'")) << err;
}

TEST(NetworkNodes, AStrokeLeavingTheCylinderStopsTheRunWithTimeAndReason) {
  const ModelFile file = parse_model_text(falling_arm(1.0), "circuit.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  long steps = 0;
  try {
    for (; steps < 3000; ++steps) sim.step();
    FAIL() << "the arm fell 3 s without the rod bottoming out";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(has(what, "subsystem 'cyl'")) << what;
    EXPECT_TRUE(has(what, "s = ")) << what;
    EXPECT_GT(e.time(), 0.05);
    EXPECT_EQ(e.step(), steps + 1);
    // The last accepted state is kept: the rod end is still inside.
    EXPECT_GT(sim.outputs()[sim.output_index("cyl.s")], 1.0 - 1e-9);
  }
}

}  // namespace
}  // namespace mh
