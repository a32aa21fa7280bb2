// The minimum-pressure (cavitation) limit of the volume and the cylinder
// chambers (plugins/components/hydraulics/gas_release.hpp): off by default the volume is
// bit-for-bit what it was; on, its row gains the released gas's storage
// C_g(p) dp/dt of Boyle's law above p_min, with an analytic jacobian; and a
// closed chamber pulled by a falling load keeps its pressure above p_min,
// where it follows the closed form of the gas taking up the lost volume,
// while without the limit the same run pulls it below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "plugins/fake_host.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

constexpr double kV = 1e-4, kBh = 550e6, kBoil = 1500e6;
constexpr double kPmin = 2e3, kAlpha = 1e-3, kPref = 1e5;  // vapour pressure of oil, ~2 kPa

// Boyle's law above p_min with q the smooth floor (eps = 1e-4 x_r): C_g = -dV_g/dp.
double gas_capacitance(double volume, double p) {
  const double xr = kPref - kPmin, eps = 1e-4 * xr, x = p - kPmin;
  const double r = std::sqrt(x * x + 4 * eps * eps);
  const double r_plus_x = x >= 0 ? r + x : 4 * eps * eps / (r - x);  // no cancellation below
  const double q = 0.5 * r_plus_x, dq = 0.5 * r_plus_x / r;
  return kAlpha * volume * xr * dq / (q * q);
}

struct VolumeFixture {
  FakeNetwork net;
  FakeHost host{net, "hose"};
  std::unique_ptr<Instance> volume;
  mh_status status = MH_ERROR;
  explicit VolumeFixture(bool limit) {
    host.numbers = {{"volume", kV}, {"bulk_modulus", kBh}, {"fluid_bulk_modulus", kBoil}};
    if (limit) {
      host.numbers["minimum_pressure"] = kPmin;
      host.numbers["gas_fraction"] = kAlpha;
      host.numbers["gas_reference_pressure"] = kPref;
    }
    host.port_nodes = {{"p", "n"}};
    volume = std::make_unique<Instance>("volume", host);
    status = volume->setup();
  }
  Evaluation at(double p, double pdot) const {
    Evaluation e(net);
    e.y[0] = p;
    e.ydot[0] = pdot;
    return e;
  }
};

TEST(CavitationLimit, OffByDefaultTheVolumeIsBitIdentical) {
  VolumeFixture plain(false);
  ASSERT_EQ(plain.status, MH_OK);
  for (double p : {-1e6, 0.0, 1e5, 2e7}) {
    Evaluation e = plain.at(p, 3e7);
    ASSERT_EQ(e.run(*plain.volume), MH_OK);
    EXPECT_EQ(e.residual[0], kV * (1.0 / kBoil + 1.0 / kBh) * 3e7);
  }
}

TEST(CavitationLimit, VolumeAddsTheGasStorageOfBoylesLawAboveTheLimit) {
  VolumeFixture f(true);
  ASSERT_EQ(f.status, MH_OK) << f.host.all_logs();
  const double c0 = kV * (1.0 / kBoil + 1.0 / kBh);
  for (double p : {-5e4, kPmin, 1e4, kPref, 1e6, 2e7}) {
    Evaluation e = f.at(p, -2e6);
    ASSERT_EQ(e.run(*f.volume), MH_OK);
    const double expected = (c0 + gas_capacitance(kV, p)) * -2e6;
    EXPECT_NEAR(e.residual[0], expected, 1e-12 * std::abs(expected)) << p;
  }
  // Far above p_min the gas is Boyle's alpha V p_ref-ish / x^2 and small beside the oil.
  EXPECT_NEAR(gas_capacitance(kV, 1e6), kAlpha * kV * (kPref - kPmin) / std::pow(1e6 - kPmin, 2),
              1e-6 * gas_capacitance(kV, 1e6));
  EXPECT_LT(gas_capacitance(kV, 1e6), 0.2 * c0);
  // Towards p_min it outgrows the oil's by orders of magnitude: the pressure cannot fall further.
  EXPECT_GT(gas_capacitance(kV, kPmin + 100.0), 1e5 * c0);
}

TEST(CavitationLimit, VolumeJacobianMatchesCentralDifferencesAcrossTheLimit) {
  VolumeFixture f(true);
  ASSERT_EQ(f.status, MH_OK);
  double worst = 0.0;
  // Below p_min + a few eps only: deeper, C_g is flat to 1e-11 over a difference step and the
  // central differences drown in round-off.
  for (double p : {kPmin - 20.0, kPmin + 50.0, 3e4, kPref, 5e6})
    worst = std::max(worst, jacobian_error(*f.volume, f.at(p, -1e6)));
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] volume with cavitation limit: jacobian max relative error %.3g\n",
              worst);
}

TEST(CavitationLimit, GasOptionsWithoutTheLimitOrOutOfRangeAreRefused) {
  for (const auto& [key, value] : std::vector<std::pair<std::string, double>>{
           {"gas_fraction", 0.0}, {"gas_fraction", 1.0}, {"gas_reference_pressure", 1e3}}) {
    VolumeFixture f(true);
    f.host.numbers[key] = value;
    f.host.option_errors.clear();
    Instance again("volume", f.host);
    EXPECT_EQ(again.setup(), MH_ERROR) << key;
    EXPECT_EQ(f.host.option_errors, std::vector<std::string>{key}) << key;
  }
  for (const char* key : {"gas_fraction", "gas_reference_pressure"}) {
    VolumeFixture f(false);
    f.host.numbers[key] = 1e-2;
    f.host.option_errors.clear();
    Instance again("volume", f.host);
    EXPECT_EQ(again.setup(), MH_ERROR) << key;
    EXPECT_EQ(f.host.option_errors, std::vector<std::string>{key}) << key;
  }
}

TEST(CavitationLimit, CylinderChambersGainTheGasStorageWithAMatchingJacobian) {
  FakeNetwork net;
  FakeHost host(net, "cylinder");
  host.numbers = {{"piston_diameter", 0.06},
                  {"rod_diameter", 0.03},
                  {"length", 1.0},
                  {"chamber_bulk_modulus", 31500e6},
                  {"fluid_bulk_modulus", 1500e6},
                  {"efficiency", 0.9},
                  {"minimum_pressure", kPmin},
                  {"gas_fraction", kAlpha},
                  {"gas_reference_pressure", kPref}};
  host.point_positions = {{"a", {0.0, 0.0, 1.5}}, {"b", {0.0, 0.0, 0.0}}};
  host.port_nodes = {{"A", "nA"}, {"B", "nB"}};
  Instance cylinder("cylinder", host);
  ASSERT_EQ(cylinder.setup(), MH_OK) << host.all_logs();
  const size_t a = static_cast<size_t>(host.port("A").index);
  const size_t b = static_cast<size_t>(host.port("B").index);
  const double a2 = 3.14159265358979323846 * 0.06 * 0.06 / 4;
  const double a3 = 3.14159265358979323846 * (0.06 * 0.06 - 0.03 * 0.03) / 4;
  const double compliance = 1.0 / 1500e6 + 1.0 / 31500e6;
  double worst = 0.0;
  // Where the gas counts (at 8 MPa its d/dp term is 1e-11 of the row: below differencing's reach).
  for (double pa : {kPmin + 30.0, 4e4, 3e5}) {
    Evaluation e(net, 2);
    e.point_p = {0.0, 0.0, 1.5, 0.0, 0.0, -0.1};  // s = 1.6: l2 = 0.6, l3 = 0.4
    e.point_v = {0.0, 0.0, 0.0, 0.0, 0.0, -0.2};  // sdot = 0.2
    e.y[a] = pa;
    e.y[b] = 3e6;
    e.ydot[a] = -4e5;
    e.ydot[b] = 2e6;
    ASSERT_EQ(e.run(cylinder), MH_OK);
    const double row_a =
        a2 * 0.6 * compliance * -4e5 + a2 * 0.2 + gas_capacitance(a2 * 1.0, pa) * -4e5;
    const double row_b =
        a3 * 0.4 * compliance * 2e6 - a3 * 0.2 + gas_capacitance(a3 * 1.0, 3e6) * 2e6;
    EXPECT_NEAR(e.residual[a], row_a, 1e-9 * std::abs(row_a)) << pa;
    EXPECT_NEAR(e.residual[b], row_b, 1e-9 * std::abs(row_b)) << pa;
    worst = std::max(worst, jacobian_error(cylinder, e));
  }
  EXPECT_LT(worst, 1e-6);
}

// A 500 kg slider hangs on a vertical cylinder whose piston side (node nA: a
// hose and the chamber) is closed; its rod side drains to the tank. Gravity
// pulls the rod out, the closed chamber grows and its pressure falls.
std::string hanging_model(bool limit) {
  const std::string hose_limit = limit ? ", minimum_pressure: 2e3, gas_fraction: 1e-3" : "";
  const std::string chamber_limit =
      limit ? "    minimum_pressure: 2e3\n    gas_fraction: 1e-3\n" : "";
  return R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: pulled-chamber
gravity: [0, 0, -9.81]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 500
    com: [0, 0, 0]
    inertia: [1, 1, 1]
    z0: 0
subsystems:
  - {name: VA, type: volume, ports: {p: nA}, volume: 2e-4, bulk_modulus: 550e6,
     fluid_bulk_modulus: 1500e6, initial_pressure: 1e5)" +
         hose_limit + R"(}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5, states: {q: null}}
  - name: cylinder
    type: cylinder
    points:
      a: {body: ground, at: [0, 0, 1.5]}
      b: {body: slider, at: [0, 0, 0]}
    ports: {A: nA, B: return}
    piston_diameter: 0.06
    rod_diameter: 0.03
    length: 1.0
    chamber_bulk_modulus: 31500e6
    fluid_bulk_modulus: 1500e6
    efficiency: 0.9
    outputs: {s: s}
)" + chamber_limit +
         R"(nodes: {return: null, nA: pA}
formulation: open-loop
solver: {dt: 0.0005, t_end: 0.25}
)";
}

TEST(CavitationLimit, ClosedChamberPulledByItsLoadStaysAboveTheLimitAndFollowsBoylesLaw) {
  const std::string model = hanging_model(true);
  const ModelFile file = parse_model_text(model, "pulled.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const int pa = sim.state_index("pA"), s_out = sim.output_index("s");
  ASSERT_GE(pa, 0);
  ASSERT_GE(s_out, 0);
  double lowest = 1e300;
  ASSERT_NO_THROW({
    while (sim.time() < 0.25 - 1e-9) {
      sim.step();
      lowest = std::min(lowest, sim.states()[pa]);
    }
  });
  const double pulled = sim.outputs()[s_out] - 1.5;  // m the rod came out
  EXPECT_GT(pulled, 0.05);
  EXPECT_GT(lowest, kPmin);
  // Boyle: the gas of the hose and the chamber (alpha of 2e-4 m^3 and of A2 l) takes the volume
  // the chamber gained, A2 * pulled (the oil's own expansion, ~1e-5 of it, neglected).
  const double a2 = 3.14159265358979323846 * 0.06 * 0.06 / 4, xr = kPref - kPmin;
  const double gas0 = kAlpha * (2e-4 + a2 * 1.0);  // m^3 at p_ref
  const double expected = kPmin + xr * gas0 / (gas0 + a2 * pulled);
  EXPECT_NEAR(sim.states()[pa], expected, 0.02 * (expected - kPmin));
  std::printf("[ measured ] pulled %.4g m: p_A %.6g Pa (Boyle %.6g Pa), lowest %.6g Pa > %.0f Pa\n",
              pulled, sim.states()[pa], expected, lowest, kPmin);
}

TEST(CavitationLimit, WithoutTheLimitTheSamePullDrivesThePressureNegative) {
  const ModelFile file = parse_model_text(hanging_model(false), "pulled.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const int pa = sim.state_index("pA");
  double lowest = 1e300;
  try {
    while (sim.time() < 0.25 - 1e-9) {
      sim.step();
      lowest = std::min(lowest, sim.states()[pa]);
    }
  } catch (const SimulationError&) {
  }
  EXPECT_LT(lowest, 0.0);  // unphysical: what the limit is for
}

}  // namespace
}  // namespace mh::test
