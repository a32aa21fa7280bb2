// The example hydraulic component examples/accumulator (gas-accumulator),
// built against the installed SDK alone (build_examples.cmake), against
// closed forms: a charge through a throttle ends at the polytropic volume
// V = V0 (p0/p)^(1/n) with the stored energy integral_V^V0 p dV, the energy it
// reports equals the integral of p q dt, its analytic jacobian equals
// differences, and in models/fourbar-accumulator.yaml the run's energy
// balance carries its stored energy with both shipped formulations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// The build's plugins and the example gas-accumulator.
const PluginRegistry& plugins() {
  return test::build_plugins_with(std::string(mh::test::paths::examples_dir) +
                                  "/accumulator/gas-accumulator.so");
}

// A free slider (no mechanics to speak of) and a node n: the accumulator
// (precharged to 2 MPa), charged from a pressure source at 8 MPa through a
// throttle, from `initial` Pa.
std::string charge_model(double exponent, double initial = 2.5e6) {
  return R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: 1.0
    com: [0, 0, 0]
    inertia: [1, 1, 1]
subsystems:
  - name: acc
    type: gas-accumulator
    ports: {p: n}
    precharge_pressure: 2e6
    gas_volume: 1e-3
    polytropic_exponent: )" +
         std::to_string(exponent) + R"(
    oil_volume: 1e-7
    initial_pressure: )" +
         std::to_string(initial) + R"(
    outputs: {V_gas: V_gas, q: q, E_gas: E_gas}
  - name: source
    type: pressure-source
    ports: {p: s}
    pressure: 8e6
  - name: line
    type: throttle
    ports: {a: s, b: n}
    area: 1e-5
    discharge_coefficient: 0.8
    density: 850
nodes: {s: null, n: p}
formulation: open-loop
solver: {dt: 0.001, t_end: 6}
)";
}

struct Charge {
  double v_start = 0.0, v_end = 0.0, e_end = 0.0, p_end = 0.0;
  double max_balance = 0.0;  // max |E_gas - integral p q dt| (J)
  double max_energy = 0.0;   // max |E_gas| (J)
};

Charge charge(double exponent) {
  const ModelFile file = parse_model_text(charge_model(exponent), "charge.yaml");
  Simulation sim(file, plugins());
  sim.start();
  const int p = sim.state_index("p");
  const int v = sim.output_index("V_gas"), q = sim.output_index("q"), e = sim.output_index("E_gas");
  Charge c;
  c.v_start = sim.outputs()[v];
  double pq_k = sim.states()[p] * sim.outputs()[q], integral = 0.0;
  const double e0 = sim.outputs()[e];
  while (sim.time() < 6.0 - 1e-9) {
    sim.step();
    const double pq = sim.states()[p] * sim.outputs()[q];
    integral += 0.5 * 1e-3 * (pq_k + pq);  // trapezoidal, as the integrator ties p to q
    pq_k = pq;
    c.max_balance = std::max(c.max_balance, std::abs(sim.outputs()[e] - e0 - integral));
    c.max_energy = std::max(c.max_energy, std::abs(sim.outputs()[e]));
  }
  c.v_end = sim.outputs()[v];
  c.e_end = sim.outputs()[e];
  c.p_end = sim.states()[p];
  return c;
}

TEST(GasAccumulator, GasVolumeStaysAtV0BelowThePrechargeAndFollowsPVnAbove) {
  for (const double initial : {1e6, 3e6}) {
    const ModelFile file = parse_model_text(charge_model(1.4, initial), "charge.yaml");
    Simulation sim(file, plugins());
    sim.start();
    const double v = sim.outputs()[sim.output_index("V_gas")];
    const double e = sim.outputs()[sim.output_index("E_gas")];
    if (initial < 2e6) {  // on its stop: V = V0, nothing stored
      EXPECT_DOUBLE_EQ(v, 1e-3);
      EXPECT_DOUBLE_EQ(e, 0.0);
    } else {
      EXPECT_NEAR(v, 1e-3 * std::pow(2e6 / initial, 1.0 / 1.4), 1e-15);
      EXPECT_GT(e, 0.0);
    }
  }
}

TEST(GasAccumulator, IsothermalChargeEndsAtBoylesVolumeWithItsStoredWork) {
  const Charge c = charge(1.0);
  EXPECT_NEAR(c.v_start, 1e-3 * 2e6 / 2.5e6, 1e-15);       // p V = p0 V0 at the start
  EXPECT_NEAR(c.p_end, 8e6, 1.0);                          // no flow left through the throttle
  EXPECT_NEAR(c.v_end, 1e-3 * 2e6 / 8e6, 1e-9);            // p V = p0 V0
  EXPECT_NEAR(c.e_end, 2e6 * 1e-3 * std::log(4.0), 1e-3);  // p0 V0 ln(V0/V)
  EXPECT_LT(c.max_balance, 1e-6 * c.max_energy);           // E = integral p q dt
}

TEST(GasAccumulator, AdiabaticChargeEndsAtThePolytropicVolumeWithItsStoredWork) {
  const double n = 1.4, p0 = 2e6, v0 = 1e-3, ps = 8e6;
  const Charge c = charge(n);
  const double v = v0 * std::pow(p0 / ps, 1.0 / n);  // p V^n = p0 V0^n
  EXPECT_NEAR(c.p_end, ps, 1.0);
  EXPECT_NEAR(c.v_end, v, 1e-9);
  EXPECT_NEAR(c.e_end,
              p0 * std::pow(v0, n) * (std::pow(v, 1.0 - n) - std::pow(v0, 1.0 - n)) / (n - 1.0),
              1e-3);
  // Adiabatic compression to the same pressure stores less than isothermal.
  EXPECT_LT(c.e_end, p0 * v0 * std::log(ps / p0));
  EXPECT_LT(c.max_balance, 1e-6 * c.max_energy);
}

TEST(GasAccumulator, AnalyticJacobianEqualsForwardDifferencesWhileCharging) {
  const ModelFile file = parse_model_text(charge_model(1.4), "charge.yaml");
  Simulation sim(file, plugins());
  sim.start();
  const int p = sim.state_index("p");
  while (sim.states()[p] < 3e6) sim.step();  // above the precharge, gas compressing
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_fd = sim.finite_difference_tangent();
  // The node's diagonal entry: c_v (C_oil + C_gas) + dC_gas/dp dp/dt - dq_throttle/dp.
  const Eigen::Index k = sim.num_mechanical_unknowns() + p;
  EXPECT_GT(std::abs(J_fd(k, k)), 0.0);
  EXPECT_NEAR(J(k, k), J_fd(k, k), 1e-6 * std::abs(J_fd(k, k)));
}

// models/fourbar-accumulator.yaml: the host's balance (stored_energy) carries
// the gas's energy, which equals the work the supply node did on it, and the
// mechanism's own balance stays as tight as the four-bar's.
void expect_fourbar_accumulator_balances(const std::string& formulation) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar-accumulator.yaml"));
  Simulation sim(file, plugins(), RunChoices{formulation, "", std::nullopt, std::nullopt});
  sim.start();
  const int ps = sim.state_index("p_s");
  const int q = sim.output_index("q_acc"), e = sim.output_index("E_gas");
  ASSERT_GE(ps, 0);
  ASSERT_GE(e, 0);
  const double e0 = sim.outputs()[e];
  double pq_k = sim.states()[ps] * sim.outputs()[q], integral = 0.0;
  double max_balance = 0.0, max_stored = 0.0, max_drift = 0.0, min_ps = sim.states()[ps];
  while (sim.time() < 10.0 - 1e-9) {
    sim.step();
    const double pq = sim.states()[ps] * sim.outputs()[q];
    integral += 0.5 * 1e-3 * (pq_k + pq);
    pq_k = pq;
    EXPECT_NEAR(sim.stored_energy(), sim.outputs()[e] - e0, 1e-9 * e0);
    max_balance = std::max(max_balance, std::abs(sim.stored_energy() - integral));
    max_stored = std::max(max_stored, std::abs(sim.stored_energy()));
    max_drift = std::max(max_drift, std::abs(sim.drift()));
    min_ps = std::min(min_ps, sim.states()[ps]);
  }
  EXPECT_LT(min_ps, 7.2e6);      // the valve's demand sags the supply line
  EXPECT_GT(max_stored, 100.0);  // and the accumulator delivers (J)
  EXPECT_LT(max_balance, 1e-4 * max_stored);
  EXPECT_LT(max_drift, 0.1);  // J, as the four-bar without it
}

TEST(GasAccumulator, FourBarWithAccumulatorBalancesEnergyWithDoubleStep) {
  expect_fourbar_accumulator_balances("double-step");
}

TEST(GasAccumulator, FourBarWithAccumulatorBalancesEnergyWithPenalty) {
  expect_fourbar_accumulator_balances("penalty");
}

}  // namespace
}  // namespace mh
