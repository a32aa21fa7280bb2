// The excavator (models/excavator.yaml, docs/machines.md) end to end: a 3D
// machine with ten coordinates, three loops closed by spherical cut joints
// out of the boom plane, five cylinders on four valves fed by one pump. The
// digging part of the cycle (dig, lift and swing: up to four levers at once)
// runs with both formulations; the whole 22 s cycle once, with double-step.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDigEnd = 8.0;  // s: dig (1-5 s), boom up from 5 s, swing from 6.5 s
const char* const kPressures[] = {"p_supply",   "p_boom_a",   "p_boom_b", "p_arm_a", "p_arm_b",
                                  "p_bucket_a", "p_bucket_b", "p_slew_a", "p_slew_b"};

std::string model_text() {
  std::ifstream in(test::source_path("models/excavator.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The model with every valve's reference replaced by `reference`, but
// `valve`'s by `valve_reference`.
ModelFile model_with_references(const std::string& reference, const std::string& valve = "",
                                const std::string& valve_reference = "") {
  std::string text = model_text();
  if (!valve.empty()) {
    const size_t at = text.find("reference: ", text.find("name: " + valve));
    text.replace(at, text.find('\n', at) - at, "reference: " + valve_reference + " # edited");
  }
  text = std::regex_replace(text, std::regex("reference: \\[\\[[^\\n]*\\]\\]\\n"),
                            "reference: " + reference + "\n");
  // The levers are the model's inputs: their tables are the references.
  text = std::regex_replace(text, std::regex("table: \\[\\[[^\\n]*\\]\\]\\}\\n"),
                            "table: " + reference + "}\n");
  return parse_model_text(text, "excavator (edited)", test::source_path("models"));
}

struct CycleRun {
  std::vector<Eigen::VectorXd> z, p;  // every step, t = 0 first
  Eigen::VectorXd z0;
  double max_drift = 0.0, max_work = 0.0, max_phi = 0.0;
  double t_end = 0.0;
};

CycleRun run_cycle(const ModelFile& file, const std::string& formulation, double t_end) {
  Simulation sim(file, test::build_plugins(), RunChoices{formulation, "", 1e-3, t_end});
  sim.start();
  std::vector<int> cols;
  for (const char* name : kPressures) {
    cols.push_back(sim.state_index(name));
    EXPECT_GE(cols.back(), 0) << name;
  }
  const auto pressures = [&] {
    Eigen::VectorXd p(static_cast<Eigen::Index>(cols.size()));
    for (size_t i = 0; i < cols.size(); ++i)
      p[static_cast<Eigen::Index>(i)] = sim.states()[cols[i]];
    return p;
  };
  CycleRun r;
  r.z0 = sim.z();
  r.z.push_back(sim.z());
  r.p.push_back(pressures());
  const long steps = std::lround(t_end / 1e-3);
  for (long k = 1; k <= steps; ++k) {
    sim.step();
    r.z.push_back(sim.z());
    r.p.push_back(pressures());
    r.max_drift = std::max(r.max_drift, std::abs(sim.drift()));
    r.max_work = std::max(r.max_work, std::abs(sim.work()));
    r.max_phi = std::max(r.max_phi, sim.phi_norm());
  }
  r.t_end = sim.time();
  return r;
}

// The digging part of the cycle, run once per process and formulation.
const CycleRun& dig(const std::string& formulation) {
  static std::map<std::string, CycleRun> runs;
  auto it = runs.find(formulation);
  if (it == runs.end())
    it = runs.emplace(formulation,
                      run_cycle(load_model_file(test::source_path("models/excavator.yaml")),
                                formulation, kDigEnd))
             .first;
  return it->second;
}

double max_difference(const std::vector<Eigen::VectorXd>& a,
                      const std::vector<Eigen::VectorXd>& b) {
  double d = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    d = std::max(d, (a[i] - b[i]).lpNorm<Eigen::Infinity>());
  return d;
}

TEST(Excavator, DigAndLiftMovesBoomArmBucketAndSlewTogether) {
  const CycleRun& ds = dig("double-step");
  const Eigen::VectorXd moved = (ds.z.back() - ds.z0).cwiseAbs();
  EXPECT_GT(moved[0], 10.0 * kPi / 180.0);  // slew
  EXPECT_GT(moved[1], 10.0 * kPi / 180.0);  // boom
  EXPECT_GT(moved[2], 30.0 * kPi / 180.0);  // arm
  EXPECT_GT(moved[3], 20.0 * kPi / 180.0);  // bucket
}

TEST(Excavator, DoubleStepAndPenaltyAgreeToTenMicroradiansAndTenKilopascals) {
  const CycleRun& ds = dig("double-step");
  const CycleRun& pen = dig("penalty");
  ASSERT_EQ(ds.z.size(), pen.z.size());
  const double dz = max_difference(ds.z, pen.z), dp = max_difference(ds.p, pen.p);
  std::printf("max |z_ds - z_pen| = %.3e rad, max |p_ds - p_pen| = %.3e Pa over %.0f s\n", dz, dp,
              kDigEnd);
  EXPECT_LT(dz, 1e-5);
  EXPECT_LT(dp, 1e4);
}

TEST(Excavator, MechanicalEnergyBalanceClosesToATenThousandthOfTheActuatorWork) {
  for (const char* formulation : {"double-step", "penalty"}) {
    const CycleRun& r = dig(formulation);
    std::printf("%s: max |drift| = %.3e J, max |W| = %.3e J\n", formulation, r.max_drift,
                r.max_work);
    EXPECT_GT(r.max_work, 1e4) << formulation;  // the cylinders really work
    EXPECT_LT(r.max_drift, 1e-4 * r.max_work) << formulation;
  }
}

TEST(Excavator, DoubleStepHoldsTheCutJointsToATenBillionth) {
  EXPECT_LT(dig("double-step").max_phi, 1e-10);
}

TEST(Excavator, TheWholeDiggingCycleRunsWithDoubleStep) {
  const ModelFile file = load_model_file(test::source_path("models/excavator.yaml"));
  ASSERT_GE(file.solver.t_end, 20.0);
  const CycleRun r = run_cycle(file, "double-step", file.solver.t_end);
  EXPECT_NEAR(r.t_end, file.solver.t_end, 1e-9);
  EXPECT_LT(r.max_phi, 1e-10);
  EXPECT_LT(r.max_drift, 1e-4 * r.max_work);
  // Swung to the truck (more than 40 deg) and back.
  double slew_max = 0.0;
  for (const auto& z : r.z) slew_max = std::max(slew_max, z[0]);
  EXPECT_GT(slew_max, 40.0 * kPi / 180.0);
  EXPECT_LT(std::abs(r.z.back()[0]), 10.0 * kPi / 180.0);
}

TEST(Excavator, HeldStillWithTheValvesClosedItDoesNotDrift) {
  for (const char* formulation : {"double-step", "penalty"}) {
    const CycleRun r = run_cycle(model_with_references("[[0, 0]]"), formulation, 2.0);
    double drift = 0.0;
    for (const auto& z : r.z) drift = std::max(drift, (z - r.z0).lpNorm<Eigen::Infinity>());
    std::printf("%s: max |z - z0| over 2 s = %.3e\n", formulation, drift);
    EXPECT_LT(drift, 1e-9) << formulation;
  }
}

// Eq. 26's g: the orifice law with its laminar region below p_tr = 2 bar.
double orifice(double dp) {
  constexpr double kTransition = 2e5;
  if (std::abs(dp) >= kTransition) return std::copysign(std::sqrt(std::abs(dp)), dp);
  return std::sqrt(kTransition) * dp / kTransition;
}

// The supply line's balance at every step of the digging cycle: what the pump
// delivers leaves through the valves to the actuators (Eq. 26 from the valves'
// states and options as the file gives them), through the relief valve and the
// neutral bypass to tank, or is stored by compressing the supply hose (Eq. 23).
TEST(Excavator, PumpFlowIsTheActuatorFlowsPlusReliefPlusCompressibility) {
  const ModelFile file = load_model_file(test::source_path("models/excavator.yaml"));
  Simulation sim(file, test::build_plugins(), RunChoices{"double-step", "", 1e-3, kDigEnd});
  sim.start();
  struct Valve {
    double c;
    int u, p, a, b;
  };
  std::vector<Valve> valves;
  double capacitance = 0.0;
  for (const SubsystemSpec& s : file.subsystems) {
    if (s.type == "valve-4-3") {
      valves.push_back({s.options.at("flow_coefficient").number, sim.state_index(s.name + ".U"),
                        sim.state_index(s.ports.at("P").node),
                        sim.state_index(s.ports.at("A").node),
                        sim.state_index(s.ports.at("B").node)});
      ASSERT_EQ(s.ports.at("P").node, "supply");
    }
    if (s.type == "volume" && s.ports.at("p").node == "supply")
      capacitance +=
          s.options.at("volume").number * (1.0 / s.options.at("fluid_bulk_modulus").number +
                                           1.0 / s.options.at("bulk_modulus").number);
  }
  ASSERT_EQ(valves.size(), 4u);
  ASSERT_GT(capacitance, 0.0);
  const int supply = sim.state_index("supply");
  const int pump = sim.output_index("Q_pump");
  ASSERT_GE(supply, 0);
  ASSERT_GE(pump, 0);
  // The paths from the supply straight to tank: the relief valve and the
  // valve bank's neutral bypass, by their flow outputs.
  std::vector<int> to_tank;
  for (const SubsystemSpec& s : file.subsystems)
    if ((s.type == "relief-valve" && s.ports.at("P").node == "supply") ||
        (s.type == "throttle" && s.ports.at("a").node == "supply"))
      to_tank.push_back(sim.output_index(s.output_names.at("q")));
  ASSERT_EQ(to_tank.size(), 2u);
  double worst = 0.0, to_actuators = 0.0;
  const long steps = std::lround(kDigEnd / 1e-3);
  for (long k = 1; k <= steps; ++k) {
    sim.step();
    const Eigen::VectorXd& y = sim.states();
    double actuators = 0.0;
    for (const Valve& v : valves) {
      const double u = y[v.u];
      actuators += v.c * std::abs(u) * orifice(y[v.p] - y[u >= 0.0 ? v.a : v.b]);
    }
    const double q_pump = sim.outputs()[pump];
    const double stored = capacitance * sim.state_rates()[supply];
    double relieved = 0.0;
    for (int q : to_tank) relieved += sim.outputs()[q];
    worst = std::max(worst, std::abs(q_pump - actuators - relieved - stored) / q_pump);
    to_actuators = std::max(to_actuators, actuators / q_pump);
  }
  std::printf("max |imbalance| / pump flow = %.3e; the actuators take up to %.0f %%\n", worst,
              100.0 * to_actuators);
  EXPECT_GT(to_actuators, 0.5);  // the levers really draw on the pump
  EXPECT_LT(worst, 1e-6);
}

// The boom lowered at full lever onto its cylinders' lower end stops (s = l =
// 1.4 m), the lever held: the run goes on, the stops hold the boom, and the
// supply, dead-headed on the stalled rod sides, rises until the relief valve
// opens, at its set pressure.
TEST(Excavator, ABoomLoweredOntoItsEndStopsRunsOnAndTheReliefOpensAtItsSetPressure) {
  const ModelFile file =
      model_with_references("[[0, 0]]", "valve_boom", "[[0, 0], [0.5, 0], [0.8, -10]]");
  double cracking = 0.0, override_pressure = 0.0, l = 0.0;
  for (const SubsystemSpec& s : file.subsystems) {
    if (s.type == "relief-valve") {
      cracking = s.options.at("cracking_pressure").number;
      override_pressure = s.options.at("override_pressure").number;
    }
    if (s.name == "boom_cyl_l") l = s.options.at("length").number;
  }
  ASSERT_GT(cracking, 0.0);
  Simulation sim(file, test::build_plugins(), RunChoices{"double-step", "", 1e-3, 6.0});
  sim.start();
  const int supply = sim.state_index("supply"), stroke = sim.output_index("s_boom_l");
  const int stop = sim.output_index("boom_cyl_l.F_stop"), relief = sim.output_index("Q_relief");
  ASSERT_GE(stop, 0);
  ASSERT_GE(relief, 0);
  const double p_tank = 1e5;
  double t_contact = -1.0, max_stop = 0.0, min_stroke = 1e9;
  double p_open_min = 1e300, p_open_max = 0.0, q_relief_end = 0.0;
  bool shut_while_moving = true;
  int halvings = 0;
  for (long k = 1; k <= 6000; ++k) {
    ASSERT_NO_THROW(sim.step()) << "t = " << sim.time();
    halvings += sim.last_step().retries;
    const double s = sim.outputs()[stroke], q = sim.outputs()[relief];
    const double dp = sim.states()[supply] - p_tank;
    min_stroke = std::min(min_stroke, s);
    max_stop = std::max(max_stop, std::abs(sim.outputs()[stop]));
    if (t_contact < 0.0 && s <= l) t_contact = sim.time();
    // Shut below the set pressure, and open only at or above it.
    if (dp <= cracking) {
      EXPECT_EQ(q, 0.0) << "t = " << sim.time();
    }
    if (q > 0.0) {
      p_open_min = std::min(p_open_min, dp);
      p_open_max = std::max(p_open_max, dp);
    }
    if (t_contact < 0.0 && sim.time() > 1.0 && q > 0.0) shut_while_moving = false;
    q_relief_end = q;
  }
  std::printf(
      "contact at t = %.3f s, min stroke %.6f m (l = %.3f m), max stop force %.3e N, "
      "relief open at %.4f..%.4f MPa, %.3e m^3/s at the end, %d step halvings\n",
      t_contact, min_stroke, l, max_stop, 1e-6 * p_open_min, 1e-6 * p_open_max, q_relief_end,
      halvings);
  EXPECT_NEAR(sim.time(), 6.0, 1e-9);  // ran on
  ASSERT_GT(t_contact, 0.0);           // reached the stop
  EXPECT_GT(max_stop, 1e4);            // which carried the boom
  EXPECT_GT(min_stroke, l - 5e-3);     // penetrated by less than 5 mm
  EXPECT_TRUE(shut_while_moving);      // the boom coming down draws the pump's flow
  EXPECT_GT(q_relief_end, 0.0);        // open at the stall
  EXPECT_GE(p_open_min, cracking);     // at its set pressure
  EXPECT_LE(p_open_max, cracking + override_pressure);
}

}  // namespace
}  // namespace mh
