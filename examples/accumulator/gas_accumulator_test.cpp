// The example component's unit test, against the installed test host alone
// (monohydra::testhost, docs/plugin-guide.md): the accumulator, precharged to
// p0 = 2 MPa with V0 = 1 l of gas, charged from 8 MPa through a throttle.
// Isothermal (n = 1) the gas follows p V = p0 V0 at every step and ends
// storing p0 V0 ln(V0/V); adiabatic (n = 1.4) p V^n = p0 V0^n; the energy it
// reports is the integral of p q dt; its jacobian equals differences; and
// `monohydra check` passes on the example model it declares.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <monohydra/testhost.hpp>
#include <string>

namespace {

namespace th = monohydra::testhost;

constexpr double kP0 = 2e6;      // Pa, precharge
constexpr double kV0 = 1e-3;     // m^3, gas volume at the precharge
constexpr double kSupply = 8e6;  // Pa
constexpr double kDt = 1e-3;     // s
constexpr int kSteps = 6000;     // 6 s: the throttle's flow has died out

// A node n with the accumulator, charged from a pressure source through a
// throttle; a free slider stands in for the mechanism.
th::Model charge(double exponent) {
  return th::Model::text(R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: acc, type: gas-accumulator, ports: {p: n}, precharge_pressure: 2e6, gas_volume: 1e-3,
     polytropic_exponent: )" +
                             std::to_string(exponent) +
                             R"(, oil_volume: 1e-7, initial_pressure: 2.5e6}
  - {name: source, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: line, type: throttle, ports: {a: s, b: n}, area: 1e-5, discharge_coefficient: 0.8,
     density: 850}
nodes: {s: null, n: p}
formulation: open-loop
solver: {dt: 0.001, t_end: 6}
)",
                         "charge.yaml");
}

const th::Host& host() {
  static const th::Host h(GAS_ACCUMULATOR_LIBRARY, "gas-accumulator");
  return h;
}

struct Charge {
  th::Series s;
  std::vector<double> p, v, q, e;
};

Charge run_charge(double exponent) {
  Charge c{host().run(charge(exponent), kSteps), {}, {}, {}, {}};
  EXPECT_TRUE(c.s.ok) << c.s.status;
  c.p = c.s.column("n");  // the node's pressure (Pa)
  c.v = c.s.column("acc.V_gas");
  c.q = c.s.column("acc.q");
  c.e = c.s.column("acc.E_gas");
  return c;
}

// max |E(t) - E(0) - integral_0^t p q dt| (trapezoidal, as the integrator
// ties p to q) relative to max |E|.
double energy_balance(const Charge& c) {
  double integral = 0.0, worst = 0.0, largest = 0.0;
  for (size_t k = 1; k < c.p.size(); ++k) {
    integral += 0.5 * kDt * (c.p[k - 1] * c.q[k - 1] + c.p[k] * c.q[k]);
    worst = std::max(worst, std::abs(c.e[k] - c.e[0] - integral));
    largest = std::max(largest, std::abs(c.e[k]));
  }
  return worst / largest;
}

TEST(GasAccumulator, IsothermalChargeFollowsBoylesLawAndStoresTheIntegralOfPQ) {
  const Charge c = run_charge(1.0);
  double worst = 0.0;  // |p V - p0 V0| / (p0 V0) over the whole charge
  for (size_t k = 0; k < c.p.size(); ++k)
    worst = std::max(worst, std::abs(c.p[k] * c.v[k] - kP0 * kV0) / (kP0 * kV0));
  std::printf("  isothermal: max |p V - p0 V0| / p0 V0 %.2e, energy balance %.2e, E %.4f J\n",
              worst, energy_balance(c), c.e.back());
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(c.p.back(), kSupply, 1.0);                     // charged: no flow left
  EXPECT_NEAR(c.e.back(), kP0 * kV0 * std::log(4.0), 1e-3);  // p0 V0 ln(V0/V), J
  EXPECT_LT(energy_balance(c), 1e-6);
}

TEST(GasAccumulator, AdiabaticChargeFollowsThePolytropeAndStoresLessThanIsothermal) {
  const double n = 1.4;
  const Charge c = run_charge(n);
  double worst = 0.0;  // |p V^n - p0 V0^n| / (p0 V0^n)
  for (size_t k = 0; k < c.p.size(); ++k)
    worst = std::max(worst, std::abs(c.p[k] * std::pow(c.v[k], n) - kP0 * std::pow(kV0, n)) /
                                (kP0 * std::pow(kV0, n)));
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(c.e.back(), kP0 * kV0 * std::log(kSupply / kP0));
  EXPECT_LT(energy_balance(c), 1e-6);
}

TEST(GasAccumulator, AnalyticJacobianEqualsDifferencesWhileCharging) {
  const th::TangentComparison t = host().tangent(charge(1.4), 50);
  ASSERT_TRUE(t.failure.empty()) << t.failure;
  std::printf("  tangent after 50 steps: max error %.2e\n", t.max_error);
  EXPECT_LT(t.max_error, 1e-5) << t.worst;
}

TEST(GasAccumulator, PassesEveryCheckOnItsDeclaredExampleModel) {
  const std::string example = host().example_model();
  ASSERT_FALSE(example.empty()) << "the descriptor declares no example model";
  const th::CheckReport r = host().check(th::Model::text(example, "declared example"));
  for (const th::Check& c : r.checks)
    EXPECT_NE(c.verdict, th::Check::Verdict::failed) << c.what << ": " << c.detail;
  EXPECT_TRUE(r.passed());
}

}  // namespace
