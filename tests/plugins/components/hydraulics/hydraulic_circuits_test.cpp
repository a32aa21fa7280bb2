// The machine components in running circuits (the core, a formulation and the
// trapezoidal rule around them), against closed forms and against the
// components they generalize: the relief valve holding a node fed through a
// throttle at the pressure where the two flows balance, a check valve holding
// a volume without leakage and letting it down only to its cracking pressure,
// and the paper's
// four-bar run with its valve-4-3 replaced by a valve-table generated from the
// orifice formula, which must give the same run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A 30 MPa supply feeds node n through a throttle; a relief valve set to 20 MPa
// (2 MPa override, 100 l/min) relieves n to the tank. No mechanism (one body at
// rest).
TEST(ReliefValveCircuit, HoldsItsNodeWhereTheThrottleAndReliefFlowsBalance) {
  const std::string model = R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: relief-circuit
gravity: [0, 0, 0]
bodies:
  - {name: dummy, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0}
subsystems:
  - {name: V, type: volume, ports: {p: n}, volume: 1e-3, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 1e5}
  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 30e6, states: {q: null}}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5, states: {q: null}}
  - {name: feed, type: throttle, ports: {a: supply, b: n}, area: 8e-6,
     discharge_coefficient: 0.7, density: 850, outputs: {q: q_feed}}
  - {name: relief, type: relief-valve, ports: {P: n, T: return}, cracking_pressure: 20e6,
     override_pressure: 2e6, nominal_flow: 1.6667e-3, outputs: {q: q_relief}}
nodes: {supply: null, return: null, n: p}
formulation: open-loop
solver: {dt: 0.001, t_end: 0.5}
)";
  const ModelFile file = parse_model_text(model, "relief.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  const int p = sim.state_index("p");
  ASSERT_GE(p, 0);
  double highest = 0.0;
  ASSERT_NO_THROW({
    while (sim.time() < 0.5 - 1e-9) {
      sim.step();
      highest = std::max(highest, sim.states()[p]);
    }
  });
  // Closed form of the balance C_vt sqrt(30 MPa - p) = Q_relief(p), by bisection on the
  // relief law of docs/hydraulics.md (d = 0.1, p_tr = 2e5).
  const double cvt = 0.7 * 8e-6 * std::sqrt(2.0 / 850.0), tank = 1e5;
  auto ramp = [](double u) { return u <= 0 ? 0.0 : (u < 0.1 ? u * u / 0.2 : u - 0.05); };
  auto g = [](double dp) { return dp / std::pow(dp * dp + 4e10, 0.25); };
  const double c = 1.6667e-3 / ((ramp(1.0) - ramp(0.0)) * g(22e6));
  auto relief = [&](double pn) {
    const double dp = pn - tank, u = (dp - 20e6) / 2e6;
    return c * (ramp(u) - ramp(u - 1)) * g(dp);
  };
  double lo = 20e6, hi = 30e6;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (cvt * std::sqrt(30e6 - mid) > relief(mid) ? lo : hi) = mid;
  }
  const double balance = 0.5 * (lo + hi);
  EXPECT_GT(balance, 20e6 + tank);             // the valve is open there
  EXPECT_NEAR(sim.states()[p], balance, 1.0);  // Pa
  EXPECT_NEAR(sim.outputs()[sim.output_index("q_feed")],
              sim.outputs()[sim.output_index("q_relief")], 1e-9);
  EXPECT_LT(highest, balance + 1e3);  // no overshoot past the balance: the valve opens in time
  std::printf(
      "[ measured ] relief circuit: p %.6f MPa (closed form %.6f MPa), relief flow %.4g m^3/s\n",
      1e-6 * sim.states()[p], 1e-6 * balance, sim.outputs()[sim.output_index("q_relief")]);
}

// A 1 l volume at 10 MPa behind a check valve (cracking 0.5 MPa): facing the tank
// backwards it holds the pressure to the last bit (no leakage); facing forwards it
// lets the volume down to the tank's pressure plus the cracking pressure, where it shuts.
double check_valve_run(bool forwards, double& lowest) {
  const std::string ports = forwards ? "{A: n, B: return}" : "{A: return, B: n}";
  const std::string model = R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: check-circuit
gravity: [0, 0, 0]
bodies:
  - {name: dummy, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0}
subsystems:
  - {name: V, type: volume, ports: {p: n}, volume: 1e-3, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 10e6}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5, states: {q: null}}
  - {name: check, type: check-valve, ports: )" +
                            ports +
                            R"(, cracking_pressure: 5e5,
     override_pressure: 2e5, nominal_flow: 1e-3}
nodes: {return: null, n: p}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";
  const ModelFile file = parse_model_text(model, "check.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  const int p = sim.state_index("p");
  lowest = 1e300;
  while (sim.time() < 1.0 - 1e-9) {
    sim.step();
    lowest = std::min(lowest, sim.states()[p]);
  }
  return sim.states()[p];
}

TEST(CheckValveCircuit, HoldsAVolumeWithoutLeakageAndLetsItDownOnlyToItsCrackingPressure) {
  double lowest = 0.0;
  EXPECT_EQ(check_valve_run(false, lowest), 10e6);  // closed: not a drop leaks
  EXPECT_EQ(lowest, 10e6);
  const double end = check_valve_run(true, lowest);
  // Down to tank + cracking within 1 s; the trapezoidal rule's last step may overshoot the
  // closing point a little (0.75 kPa here: the valve shuts inside a step), and once shut
  // the volume holds exactly (the lowest pressure is the last one).
  EXPECT_NEAR(end, 1e5 + 5e5, 1e3);
  EXPECT_EQ(end, lowest);
  std::printf(
      "[ measured ] check valve letting a volume down: %.6g Pa after 1 s (tank + cracking "
      "%.6g Pa)\n",
      end, 1e5 + 5e5);
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The four-bar (models/fourbar.yaml) for 3 s, with the valve as given or as a
// valve-table holding one row: Q = C_vd * 10 V * sqrt(1 MPa) at U = 10 V, dp = 1 MPa,
// which is the orifice formula (K = C_vd U, linear from the closed centre).
TEST(ValveTableCircuit, FourBarWithAnOrificeGeneratedTableRunsAsWithValve43) {
  std::string original = read(test::source_path("models/fourbar.yaml"));
  const std::string t_end = "t_end: 10,";
  ASSERT_NE(original.find(t_end), std::string::npos);
  original.replace(original.find(t_end), t_end.size(), "t_end: 3,");
  std::string tabled = original;
  const std::string type = "type: valve-4-3", coefficient = "flow_coefficient: 2.138e-8";
  ASSERT_NE(tabled.find(type), std::string::npos);
  ASSERT_NE(tabled.find(coefficient), std::string::npos);
  tabled.replace(tabled.find(type), type.size(), "type: valve-table");
  tabled.replace(tabled.find(coefficient), coefficient.size(), "flow_table: [[10, 1e6, 2.138e-4]]");
  const ModelFile file_a = parse_model_text(original, "fourbar.yaml");  // outlive the runs
  const ModelFile file_b = parse_model_text(tabled, "fourbar-table.yaml");
  Simulation a(file_a, test::build_plugins());
  Simulation b(file_b, test::build_plugins());
  a.start();
  b.start();
  double dz = 0.0, dp = 0.0;
  while (a.time() < 3.0 - 1e-9) {
    a.step();
    b.step();
    dz = std::max(dz, (a.z() - b.z()).cwiseAbs().maxCoeff());
    dp = std::max(dp, (a.states() - b.states()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(dz, 1e-9);  // rad
  EXPECT_LT(dp, 1e-2);  // Pa (and V, m^3/s)
  std::printf(
      "[ measured ] four-bar, valve-table vs valve-4-3 over 3 s: max |dz| %.3g rad, max "
      "|dy| %.3g\n",
      dz, dp);
}

// What a host that draws the run sees of the four-bar's cylinder (visual.h):
// an actuator from its housing point a to its rod point b, the barrel as
// long as the cylinder, a fifth wider than the piston, the rod its own
// diameter, and its two chambers coloured by the nodes of its ports A and B.
TEST(HydraulicCylinder, DeclaresItsBarrelRodAndChamberPressuresAsItsLook) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  const Simulation sim(file, test::build_plugins());
  ASSERT_EQ(sim.visuals().size(), 1u);
  const Visual& v = sim.visuals().front();
  EXPECT_EQ(v.instance, "cylinder");
  EXPECT_EQ(v.kind, Visual::Kind::actuator);
  EXPECT_EQ(v.a.body, kGround);
  EXPECT_TRUE(v.a.p_B.isApprox(Eigen::Vector3d(0, -2, 0)));
  EXPECT_EQ(v.b.body, 2);
  EXPECT_TRUE(v.b.p_B.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_DOUBLE_EQ(v.barrel_length, 1.1);
  EXPECT_DOUBLE_EQ(v.barrel_diameter, 1.2 * 0.080);
  EXPECT_DOUBLE_EQ(v.rod_diameter, 0.035);
  ASSERT_GE(v.state_a, 0);
  ASSERT_GE(v.state_b, 0);
  EXPECT_EQ(sim.state_names()[static_cast<size_t>(v.state_a)], "p2");  // node n2
  EXPECT_EQ(sim.state_names()[static_cast<size_t>(v.state_b)], "p3");  // node n3
}

}  // namespace
}  // namespace mh
