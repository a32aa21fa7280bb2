// The pilot-operated valves of the hydraulics plugin (counterbalance-valve,
// pilot-check-valve; docs/hydraulics.md). Through the C ABI with a fake host:
// each opens at the pilot pressure its ratio predicts, holds with no flow
// below it, passes free flow the other way, dissipates Q dp >= 0, and its
// analytic jacobian matches central differences where it is open. In a run
// of their example models (a 1 t load on a vertical cylinder): a load held
// with the valve closed creeps by less than 1e-4 m in 5 s, and a lowering
// through the counterbalance valve never runs ahead of the pump's inflow to
// the other side (the metering) by more than a moment's 10 %, then equals it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "plugins/fake_host.hpp"

namespace mh::test {
namespace {

constexpr double kRef = 1e5;  // the drain's pressure (both valves' default)

struct PilotValve {
  FakeNetwork net;
  FakeHost host{net, "valve"};
  std::unique_ptr<Instance> valve;
  mh_status setup_status = MH_ERROR;
  int32_t a = -1, b = -1, x = -1;  // counterbalance: L, V, X; pilot check: A, B, X

  PilotValve(const std::string& id, const std::map<std::string, double>& numbers) {
    host.numbers = numbers;
    const bool cbv = id == "counterbalance-valve";
    host.port_nodes = {{cbv ? "L" : "A", "a"}, {cbv ? "V" : "B", "b"}, {"X", "x"}};
    valve = std::make_unique<Instance>(id, host);
    setup_status = valve->setup();
    if (setup_status != MH_OK) return;
    a = host.port(cbv ? "L" : "A").index;
    b = host.port(cbv ? "V" : "B").index;
    x = host.port("X").index;
  }
  Evaluation at(double p_a, double p_b, double p_x) {
    Evaluation e(net);
    e.y[a] = p_a;
    e.y[b] = p_b;
    e.y[x] = p_x;
    return e;
  }
  // The flow from the first port to the second, and its opening.
  double flow(double p_a, double p_b, double p_x, double* opening = nullptr) {
    Evaluation e = at(p_a, p_b, p_x);
    EXPECT_EQ(e.run(*valve), MH_OK);
    EXPECT_EQ(e.residual[b], -e.residual[a]);
    EXPECT_EQ(e.residual[x], 0.0) << "the pilot takes no flow";
    EXPECT_EQ(e.outputs[host.outputs.at("q")], e.residual[a]);
    if (opening != nullptr) *opening = e.outputs[host.outputs.at("x")];
    return e.residual[a];
  }
  // The pilot pressure at which the valve cracks, by bisection on q > 0
  // (A -> B for the counterbalance's L -> V, B -> A for the pilot check).
  double cracking_pilot(double p_a, double p_b, double lo, double hi, double sign) {
    for (int i = 0; i < 80; ++i) {
      const double mid = 0.5 * (lo + hi);
      (sign * flow(p_a, p_b, mid) > 0.0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

const std::map<std::string, double> kCounterbalance = {{"setting_pressure", 25e6},
                                                       {"pilot_ratio", 4.5},
                                                       {"override_pressure", 5e6},
                                                       {"nominal_flow", 1e-3}};

TEST(CounterbalanceValve, OpensAtThePilotPressureItsRatioPredicts) {
  for (const double ratio : {3.0, 4.5, 8.0}) {
    auto numbers = kCounterbalance;
    numbers["pilot_ratio"] = ratio;
    PilotValve v("counterbalance-valve", numbers);
    ASSERT_EQ(v.setup_status, MH_OK) << v.host.all_logs();
    for (const double load : {5e6, 12e6, 20e6}) {      // gauge load pressures below the setting
      const double predicted = (25e6 - load) / ratio;  // gauge: p_L + R p_X = p_set
      const double measured =
          v.cracking_pilot(kRef + load, kRef, kRef, kRef + 2.0 * predicted, 1.0) - kRef;
      EXPECT_NEAR(measured, predicted, 0.02 * predicted) << "R " << ratio << ", load " << load;
      EXPECT_NEAR(measured, predicted, 1e-6 * predicted);  // the law's own cracking: exact
    }
  }
}

TEST(CounterbalanceValve, HoldsBelowItsSettingAndLetsFreeFlowInThroughItsCheck) {
  PilotValve v("counterbalance-valve", kCounterbalance);
  ASSERT_EQ(v.setup_status, MH_OK) << v.host.all_logs();
  // Closed: any load pressure up to the setting, the pilot at drain.
  for (const double load : {0.0, 1e6, 10e6, 24.99e6, 25e6}) {
    double x = -1.0;
    EXPECT_EQ(v.flow(kRef + load, kRef, kRef, &x), 0.0) << load;
    EXPECT_EQ(x, 0.0);
  }
  // Without pilot it relieves above the setting (a thermal or shock load).
  EXPECT_GT(v.flow(kRef + 26e6, kRef, kRef), 0.0);
  // The check: V -> L once p_V - p_L exceeds its 3e4 Pa, the relief path shut.
  EXPECT_EQ(v.flow(kRef + 5e6, kRef + 5e6 + 2.9e4, kRef), 0.0);
  EXPECT_LT(v.flow(kRef + 5e6, kRef + 6e6, kRef), 0.0);
  // Fully open it passes its nominal flow at its nominal 1 MPa drop.
  double x = 0.0;
  const double q = v.flow(kRef + 20e6, kRef + 19e6, kRef + 10e6, &x);
  EXPECT_EQ(x, 1.0);  // u = 8: r(u) - r(u - 1) = 1
  EXPECT_NEAR(q, 1e-3, 1e-12);
}

TEST(CounterbalanceValve, DissipatesOnEveryPathAndItsJacobianMatchesCentralDifferences) {
  auto numbers = kCounterbalance;
  numbers["leakage"] = 1e-13;
  PilotValve v("counterbalance-valve", numbers);
  ASSERT_EQ(v.setup_status, MH_OK) << v.host.all_logs();
  double worst = 0.0;
  const double points[][3] = {{20e6, 2e6, 2e6},   {20e6, 2e6, 1.2e6}, {10e6, 9.9e6, 4e6},
                              {5e6, 6e6, 0.0},    {5e6, 5.1e6, 3e6},  {26e6, 0.1e6, 0.0},
                              {18e6, 18.5e6, 2e6}};
  for (const auto& p : points) {
    Evaluation e = v.at(kRef + p[0], kRef + p[1], kRef + p[2]);
    worst = std::max(worst, jacobian_error(*v.valve, e));
    const mh_subsystem_eval rec = e.record();
    double stored = -1.0, dissipation = -1.0;
    ASSERT_EQ(v.valve->api()->energy(v.valve->api(), &rec, &stored, &dissipation), MH_OK);
    EXPECT_EQ(stored, 0.0);
    EXPECT_GE(dissipation, 0.0);
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] counterbalance-valve jacobian max relative error %.3g\n", worst);
}

const std::map<std::string, double> kPilotCheck = {{"pilot_ratio", 4.0}, {"nominal_flow", 1e-3}};

TEST(PilotCheckValve, IsACheckValveUntilItsPilotOpensItAtThePredictedPressure) {
  PilotValve v("pilot-check-valve", kPilotCheck);
  ASSERT_EQ(v.setup_status, MH_OK) << v.host.all_logs();
  // Free flow A -> B above its 3e4 Pa cracking, none back without pilot.
  EXPECT_EQ(v.flow(kRef + 2.9e4, kRef, kRef), 0.0);
  EXPECT_GT(v.flow(kRef + 1e6, kRef, kRef), 0.0);
  for (const double load : {1e6, 10e6, 30e6}) {
    EXPECT_EQ(v.flow(kRef, kRef + load, kRef), 0.0) << load;
    // Reverse flow once R (p_X - p_ref) > p_B - p_A + p_cr.
    const double predicted = (load + 3e4) / 4.0;
    const double measured =
        v.cracking_pilot(kRef, kRef + load, kRef, kRef + 2.0 * predicted, -1.0) - kRef;
    EXPECT_NEAR(measured, predicted, 0.02 * predicted) << load;
    EXPECT_LT(v.flow(kRef, kRef + load, kRef + 1.5 * predicted), 0.0);
  }
  double worst = 0.0;
  for (const auto& p : {std::array<double, 3>{1e6, 0.0, 0.0},
                        {0.0, 10e6, 3e6},
                        {0.0, 10e6, 2.6e6},
                        {5e6, 5.05e6, 1e5}})
    worst = std::max(worst, jacobian_error(*v.valve, v.at(kRef + p[0], kRef + p[1], kRef + p[2])));
  EXPECT_LT(worst, 1e-6);
}

TEST(PilotValveOptions, BadValuesAreRefusedOnTheirKey) {
  const struct {
    const char* id;
    const char* key;
    double value;
  } cases[] = {{"counterbalance-valve", "setting_pressure", 0.0},
               {"counterbalance-valve", "pilot_ratio", -2.0},
               {"counterbalance-valve", "override_pressure", 0.0},
               {"counterbalance-valve", "leakage", -1e-12},
               {"counterbalance-valve", "check_cracking_pressure", -1.0},
               {"counterbalance-valve", "smoothing", 2.0},
               {"pilot-check-valve", "pilot_ratio", 0.0},
               {"pilot-check-valve", "cracking_pressure", -5.0},
               {"pilot-check-valve", "nominal_flow", 0.0}};
  for (const auto& c : cases) {
    auto numbers = std::string(c.id) == "counterbalance-valve" ? kCounterbalance : kPilotCheck;
    numbers[c.key] = c.value;
    PilotValve v(c.id, numbers);
    EXPECT_EQ(v.setup_status, MH_ERROR) << c.id << " " << c.key;
    EXPECT_EQ(v.host.option_errors, std::vector<std::string>{c.key}) << c.id << " " << c.key;
  }
}

// --- in a run: the example models' load -------------------------------------

constexpr double kRodArea = 0.25 * M_PI * (0.08 * 0.08 - 0.04 * 0.04);
constexpr double kInflow = 2e-4;  // m^3/s, the examples' pump

TEST(CounterbalanceValve, HoldsTheLoadWithLessThanATenthMillimetreOfCreepInFiveSeconds) {
  const std::string text = edited(
      edited(example_model("counterbalance-valve"), "[1, 0], [1.2, 2e-4], [100, 2e-4]", "[100, 0]"),
      "t_end: 2", "t_end: 5");
  const ModelFile file = parse_model_text(text, "counterbalance-hold.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const double z0 = sim.z()[0];
  double worst = 0.0;
  while (sim.time() < 5.0 - 1e-9) {
    sim.step();
    worst = std::max(worst, std::abs(sim.z()[0] - z0));
    ASSERT_EQ(sim.outputs()[sim.output_index("cbv.q")], 0.0) << "t = " << sim.time();
  }
  EXPECT_LT(worst, 1e-4);
  std::printf("[ measured ] counterbalance hold: creep %.3g m in 5 s\n", worst);
}

TEST(CounterbalanceValve, LoweringIsMeteredByTheInflowAndNeverRunsAhead) {
  const std::string text = edited(example_model("counterbalance-valve"), "t_end: 2", "t_end: 6");
  const ModelFile file = parse_model_text(text, "counterbalance-lowering.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const int sdot = sim.output_index("cylinder.sdot");
  const int rod = sim.state_index("rod");
  ASSERT_GE(sdot, 0);
  ASSERT_GE(rod, 0);
  const double metered = kInflow / kRodArea;  // the speed the pump's inflow allows
  double fastest = 0.0, lowest_rod = 1e300;
  while (sim.time() < 6.0 - 1e-9) {
    sim.step();
    fastest = std::max(fastest, -sim.outputs()[sdot]);
    lowest_rod = std::min(lowest_rod, sim.states()[rod]);
  }
  // As the valve cracks the load jumps ahead for a moment (the rod side's oil
  // is compressed as much as the pump filled it): 7 % measured; after that the
  // lowering is the metered speed.
  EXPECT_LE(fastest, 1.10 * metered) << "the load ran ahead of the metering";
  EXPECT_NEAR(-sim.outputs()[sdot], metered, 0.01 * metered) << "steady lowering";
  EXPECT_GT(lowest_rod, 0.5e5) << "the rod side never empties (no cavitation)";
  EXPECT_LT(sim.z()[0], -0.2);  // it did lower
  std::printf("[ measured ] counterbalance lowering: fastest %.4f m/s, metered %.4f m/s\n", fastest,
              metered);
}

TEST(PilotCheckValve, LiftsThroughItsFreeFlowAndThenHoldsTheLoad) {
  const std::string text = edited(example_model("pilot-check-valve"), "t_end: 2", "t_end: 7");
  const ModelFile file = parse_model_text(text, "pilot-check.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  while (sim.time() < 2.0 - 1e-9) sim.step();
  const double lifted = sim.z()[0];
  // The pump's 8e-5 m^3 (its table's integral) over the cap's area is
  // 0.0159 m, less what the line's bleed returns to tank.
  EXPECT_GT(lifted, 0.014);
  EXPECT_LT(lifted, 8e-5 / (0.25 * M_PI * 0.08 * 0.08));
  double worst = 0.0;
  while (sim.time() < 7.0 - 1e-9) {
    sim.step();
    worst = std::max(worst, std::abs(sim.z()[0] - lifted));
  }
  EXPECT_LT(worst, 1e-4);
  std::printf("[ measured ] pilot check: lifted %.4f m, creep %.3g m in 5 s\n", lifted, worst);
}

}  // namespace
}  // namespace mh::test
