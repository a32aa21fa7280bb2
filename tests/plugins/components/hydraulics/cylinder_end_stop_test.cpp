// The cylinder's end stops (plugins/components/hydraulics/end_stop.hpp, options
// end_stop_*): off by default the cylinder is bit-for-bit what it was; on,
// the stops push back with k delta + c w delta_dot past either stroke end;
// and a slider driven by a pump into its stop keeps running, resting at the
// closed-form penetration F / k, never deeper than the impact allows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "plugins/fake_host.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kD2 = 0.05, kD3 = 0.028, kLength = 1.0;  // m
const double kA2 = kPi * kD2 * kD2 / 4.0, kA3 = kPi * (kD2 * kD2 - kD3 * kD3) / 4.0;
constexpr double kStiffness = 1e8, kDamping = 1e5, kDepth = 1e-3;

// A cylinder along x from (0, 0, 0) to (1.5, 0, 0): s0 = 1.5, stroke [1, 2] m.
struct Cylinder {
  FakeNetwork net;
  FakeHost host{net, "cylinder"};
  std::unique_ptr<Instance> instance;
  mh_status status = MH_ERROR;

  explicit Cylinder(bool stops) {
    host.numbers = {
        {"piston_diameter", kD2},          {"rod_diameter", kD3},          {"length", kLength},
        {"chamber_bulk_modulus", 31500e6}, {"fluid_bulk_modulus", 1500e6}, {"efficiency", 0.9}};
    if (stops) {
      host.numbers["end_stop_stiffness"] = kStiffness;
      host.numbers["end_stop_damping"] = kDamping;
      host.numbers["end_stop_depth"] = kDepth;
    }
    host.point_positions = {{"a", {0.0, 0.0, 0.0}}, {"b", {1.5, 0.0, 0.0}}};
    host.port_nodes = {{"A", "nA"}, {"B", "nB"}};
    instance = std::make_unique<Instance>("cylinder", host);
    status = instance->setup();
  }
  Evaluation at(double s, double sdot) const {
    Evaluation e(net, 2);
    e.point_p = {0.0, 0.0, 0.0, s, 0.0, 0.0};
    e.point_v = {0.0, 0.0, 0.0, sdot, 0.0, 0.0};
    e.y[static_cast<size_t>(host.port("A").index)] = 6e6;
    e.y[static_cast<size_t>(host.port("B").index)] = 2e6;
    e.ydot[static_cast<size_t>(host.port("A").index)] = 1e7;
    e.ydot[static_cast<size_t>(host.port("B").index)] = -3e6;
    return e;
  }
};

TEST(CylinderEndStop, OffByDefaultTheCylinderIsBitIdenticalInsideItsStroke) {
  Cylinder plain(false), stopped(true);
  ASSERT_EQ(plain.status, MH_OK) << plain.host.all_logs();
  ASSERT_EQ(stopped.status, MH_OK) << stopped.host.all_logs();
  EXPECT_EQ(plain.host.outputs.count("F_stop"), 0u);  // no new column without stops
  EXPECT_EQ(stopped.host.outputs.count("F_stop"), 1u);
  for (double s : {1.01, 1.5, 1.99}) {
    for (double sdot : {-0.3, 0.0, 0.2}) {
      Evaluation a = plain.at(s, sdot), b = stopped.at(s, sdot);
      ASSERT_EQ(a.run(*plain.instance), MH_OK);
      ASSERT_EQ(b.run(*stopped.instance), MH_OK);
      for (size_t i = 0; i < a.residual.size(); ++i) EXPECT_EQ(a.residual[i], b.residual[i]);
      for (size_t i = 0; i < a.point_f.size(); ++i) EXPECT_EQ(a.point_f[i], b.point_f[i]);
    }
  }
}

TEST(CylinderEndStop, PastEitherEndTheStopPushesBackWithKDeltaPlusRampedDamping) {
  Cylinder plain(false), stopped(true);
  ASSERT_EQ(stopped.status, MH_OK);
  const double hydraulic = 6e6 * kA2 - 2e6 * kA3;
  auto smoothstep = [](double x) { return x >= 1 ? 1.0 : x * x * (3 - 2 * x); };
  struct Case {
    double s, sdot;
  };
  for (const Case& c :
       {Case{2.0004, 0.0}, Case{2.003, 0.1}, Case{0.9995, -0.2}, Case{0.99, 0.05}}) {
    EXPECT_EQ(plain.at(c.s, c.sdot).run(*plain.instance), MH_ERROR);  // the stroke left it
    Evaluation e = stopped.at(c.s, c.sdot);
    ASSERT_EQ(e.run(*stopped.instance), MH_OK) << stopped.host.all_logs();
    const bool upper = c.s > 2.0;
    const double delta = upper ? c.s - 2.0 : 1.0 - c.s;
    const double delta_dot = upper ? c.sdot : -c.sdot;
    const double contact = kStiffness * delta + kDamping * smoothstep(delta / kDepth) * delta_dot;
    const double stop = upper ? -contact : contact;  // pushes the ends apart at the lower stop
    EXPECT_NEAR(e.outputs[static_cast<size_t>(stopped.host.outputs.at("F_stop"))], stop,
                1e-9 * std::abs(stop));
    const double friction = 0.1 * std::abs(hydraulic) * std::tanh(c.sdot / 0.01);
    EXPECT_NEAR(e.point_f[3], hydraulic - friction + stop, 1e-9 * std::abs(hydraulic)) << c.s;
    // The emptied chamber stores nothing: l clamped at 0, never negative.
    const size_t empty = static_cast<size_t>(stopped.host.port(upper ? "B" : "A").index);
    EXPECT_EQ(e.residual[empty], (upper ? -kA3 : kA2) * c.sdot);
  }
}

TEST(CylinderEndStop, StoresKDeltaSquaredOverTwoAndDissipatesNonNegative) {
  Cylinder stopped(true);
  ASSERT_EQ(stopped.status, MH_OK);
  for (double sdot : {-0.5, 0.0, 0.5}) {
    Evaluation e = stopped.at(2.002, sdot);
    const mh_subsystem_eval rec = e.record();
    double stored = -1, dissipation = -1;
    ASSERT_EQ(stopped.instance->api()->energy(stopped.instance->api(), &rec, &stored, &dissipation),
              MH_OK);
    EXPECT_NEAR(stored, 0.5 * kStiffness * 0.002 * 0.002, 1e-9);
    EXPECT_GE(dissipation, 0.0);
  }
}

TEST(CylinderEndStop, DampingOrDepthWithoutStiffnessIsRefused) {
  for (const char* key : {"end_stop_damping", "end_stop_depth"}) {
    FakeNetwork net;
    FakeHost host(net, "cylinder");
    host.numbers = {{"piston_diameter", kD2},
                    {"rod_diameter", kD3},
                    {"length", kLength},
                    {"chamber_bulk_modulus", 31500e6},
                    {"fluid_bulk_modulus", 1500e6},
                    {"efficiency", 0.9},
                    {key, 1.0}};
    host.point_positions = {{"a", {0.0, 0.0, 0.0}}, {"b", {1.5, 0.0, 0.0}}};
    Instance cylinder("cylinder", host);
    EXPECT_EQ(cylinder.setup(), MH_ERROR);
    EXPECT_EQ(host.option_errors, std::vector<std::string>{key});
  }
  for (const auto& [key, value] : std::vector<std::pair<std::string, double>>{
           {"end_stop_stiffness", 0.0}, {"end_stop_damping", -1.0}, {"end_stop_depth", 0.0}}) {
    Cylinder c(false);
    c.host.numbers["end_stop_stiffness"] = kStiffness;
    c.host.numbers[key] = value;
    c.host.option_errors.clear();
    Instance again("cylinder", c.host);
    EXPECT_EQ(again.setup(), MH_ERROR) << key;
    EXPECT_EQ(c.host.option_errors, std::vector<std::string>{key});
  }
}

// A 100 kg slider on a horizontal prismatic joint, pushed out by a cylinder
// fed from a 10 MPa pump through a throttle (the rod side drains through
// another), runs 0.5 m into the upper stop at s = 2 m.
std::string slider_model(const std::string& stop_options) {
  return R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: slider-into-stop
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: 100
    com: [0, 0, 0]
    inertia: [1, 1, 1]
    z0: 0
subsystems:
  - {name: VA, type: volume, ports: {p: nA}, volume: 1e-4, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 1e5}
  - {name: VB, type: volume, ports: {p: nB}, volume: 1e-4, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 1e5}
  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 10e6, states: {q: null}}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5, states: {q: null}}
  - {name: in, type: throttle, ports: {a: supply, b: nA}, area: 1.2e-5,
     discharge_coefficient: 0.8, density: 850, outputs: {q: null}}
  - {name: out, type: throttle, ports: {a: nB, b: return}, area: 1.2e-5,
     discharge_coefficient: 0.8, density: 850, outputs: {q: null}}
  - name: cylinder
    type: cylinder
    points:
      a: {body: ground, at: [-1.5, 0, 0]}
      b: {body: slider, at: [0, 0, 0]}
    ports: {A: nA, B: nB}
    piston_diameter: 0.05
    rod_diameter: 0.028
    length: 1.0
    chamber_bulk_modulus: 31500e6
    fluid_bulk_modulus: 1500e6
    efficiency: 0.9
)" + stop_options +
         R"(
nodes: {supply: null, return: null, nA: pA, nB: pB}
formulation: open-loop
solver: {dt: 0.001, t_end: 2.5}
)";
}

TEST(CylinderEndStop, SliderDrivenIntoItsStopRunsOnAndRestsAtFOverK) {
  const std::string stops =
      "    end_stop_stiffness: 1e8\n    end_stop_damping: 1e5\n"
      "    outputs: {s: s, sdot: sdot, F_stop: F_stop}\n";
  const ModelFile file = parse_model_text(slider_model(stops), "slider.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const int s_out = sim.output_index("s"), v_out = sim.output_index("sdot");
  ASSERT_GE(s_out, 0);
  ASSERT_GE(v_out, 0);
  double deepest = 0.0, fastest = 0.0;
  ASSERT_NO_THROW({
    while (sim.time() < 2.5 - 1e-9) {
      sim.step();
      deepest = std::max(deepest, sim.outputs()[s_out] - 2.0);
      fastest = std::max(fastest, std::abs(sim.outputs()[v_out]));
    }
  });
  // At rest the pump's pressure holds the piston against the stop: k delta = pP A2 - pT A3 (no
  // friction at rest, no flow through the throttles).
  const double rest = (10e6 * kA2 - 1e5 * kA3) / kStiffness;
  const double final_delta = sim.outputs()[s_out] - 2.0;
  EXPECT_NEAR(final_delta, rest, 1e-3 * rest);
  // Bounded: the static push plus the impact's v sqrt(m / k), far below the 1 mm damping depth.
  EXPECT_GT(deepest, 0.0);
  EXPECT_LT(deepest, 10e6 * kA2 / kStiffness + fastest * std::sqrt(100.0 / kStiffness));
  EXPECT_GT(fastest, 0.1);  // it did run into the stop
  std::printf("[ measured ] impact %.3g m/s, deepest %.4g mm, at rest %.6g mm (F/k %.6g mm)\n",
              fastest, 1e3 * deepest, 1e3 * final_delta, 1e3 * rest);
}

TEST(CylinderEndStop, WithoutStopsTheSameRunFailsWhereTheStrokeEnds) {
  const ModelFile file = parse_model_text(slider_model("    outputs: {s: s}\n"), "slider.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  try {
    while (sim.time() < 2.5 - 1e-9) sim.step();
    ADD_FAILURE() << "ran through the end of the stroke";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("stroke left the cylinder"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mh::test
