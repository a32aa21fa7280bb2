// The load-sensing components of the hydraulics plugin (variable-pump,
// ls-valve-section, shuttle-valve; docs/hydraulics.md). In runs of their
// example circuits: the pump holds its pressure at the load's plus the LS
// margin within 1 % with one section open; a pre-compensated section's flow
// changes by less than 2 % when its load doubles and equals C_vd U sqrt(dp_c);
// post-compensated sections share a pump short of flow in proportion to
// their openings; the cut-off and the power limit bound the pump; the shuttle
// network's output is the highest load pressure. Through the C ABI: every
// analytic jacobian against central differences.
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

// The model run to its end (1 s: every transient over); the run itself.
std::unique_ptr<Simulation> settled(const std::string& text, ModelFile& file) {
  file = parse_model_text(text, "load-sensing.yaml");
  auto sim = std::make_unique<Simulation>(file, build_plugins());
  sim->start();
  while (sim->time() < file.solver.t_end - 1e-9) sim->step();
  return sim;
}
double state(const Simulation& s, const std::string& name) {
  const int i = s.state_index(name);
  EXPECT_GE(i, 0) << name;
  return i < 0 ? NAN : s.states()[i];
}
double output(const Simulation& s, const std::string& name) {
  const int i = s.output_index(name);
  EXPECT_GE(i, 0) << name;
  return i < 0 ? NAN : s.outputs()[i];
}

constexpr double kMargin = 2e6, kCvd = 2e-8, kCompensator = 1e6;

TEST(VariablePump, HoldsTheLoadPressurePlusItsMarginWithOneSectionOpen) {
  for (const double load : {5e6, 10e6, 20e6}) {
    ModelFile file;
    const auto sim = settled(edited(example_model("variable-pump"), "pressure: 10e6",
                                    "pressure: " + std::to_string(load)),
                             file);
    const double p_pump = state(*sim, "supply");
    const double target = load + kMargin;
    EXPECT_NEAR(p_pump, target, 0.01 * target) << "load " << load;
    std::printf("[ measured ] LS pump at a %.0f MPa load: p_P - p_load = %.4f MPa (margin 2)\n",
                load / 1e6, (p_pump - load) / 1e6);
  }
}

TEST(LsValveSection, PreCompensatedFlowChangesLessThanTwoPercentWhenTheLoadDoubles) {
  double flows[2] = {0.0, 0.0};
  const double loads[2] = {8e6, 16e6};
  for (int k = 0; k < 2; ++k) {
    ModelFile file;
    const auto sim = settled(edited(example_model("variable-pump"), "pressure: 10e6",
                                    "pressure: " + std::to_string(loads[k])),
                             file);
    flows[k] = output(*sim, "section.q");
    // The compensator's drop across the edge: C_vd U sqrt(dp_c), U = 5 V.
    EXPECT_NEAR(flows[k], kCvd * 5.0 * std::sqrt(kCompensator), 0.01 * flows[k]);
  }
  EXPECT_LT(std::abs(flows[1] - flows[0]), 0.02 * flows[0]);
  std::printf("[ measured ] pre-compensated flow at 8 and 16 MPa: %.6g and %.6g m^3/s\n", flows[0],
              flows[1]);
}

TEST(LsValveSection, PostCompensatedSectionsShareAShortPumpInProportionToTheirOpenings) {
  ModelFile file;
  const auto sim = settled(example_model("ls-valve-section"), file);
  const double q1 = output(*sim, "section1.q"), q2 = output(*sim, "section2.q");
  const double pump_max = 1e-6 * 100.0;  // D w: the pump is at full stroke
  EXPECT_NEAR(state(*sim, "pump.eps"), 1.0, 1e-3);
  EXPECT_NEAR(q1 + q2, pump_max, 0.01 * pump_max);
  EXPECT_NEAR(q1 / q2, 4.0 / 8.0, 0.01 * 0.5) << "openings 4 V and 8 V";
  // Each asked for C_vd U sqrt(margin): together 2.4 times what the pump gives.
  EXPECT_GT(kCvd * 12.0 * std::sqrt(kMargin), 2.0 * pump_max);
  // The shuttle sends the higher load pressure to the pump and the compensators.
  EXPECT_NEAR(state(*sim, "ls"), 10e6, 1e-3 * 10e6);
  EXPECT_NEAR(state(*sim, "ls1"), 5e6, 1e-3 * 5e6);
  std::printf("[ measured ] flow sharing: q1 / q2 = %.5f (openings 0.5), q1 + q2 = %.6g m^3/s\n",
              q1 / q2, q1 + q2);
}

TEST(VariablePump, CutOffAndPowerLimitBoundThePump) {
  {  // a cut-off below load + margin: the pump holds the cut-off instead
    ModelFile file;
    const auto sim = settled(
        edited(example_model("variable-pump"), "cutoff_pressure: 30e6", "cutoff_pressure: 11e6"),
        file);
    EXPECT_NEAR(state(*sim, "supply"), 11e6, 0.01 * 11e6);
  }
  {  // 0.8 kW where the section asks for 1.2 kW
    ModelFile file = parse_model_text(
        edited(example_model("variable-pump"), "max_power: 60e3", "max_power: 800"), "p.yaml");
    Simulation sim(file, build_plugins());
    sim.start();
    double highest = 0.0;
    while (sim.time() < 1.0 - 1e-9) {
      sim.step();
      highest = std::max(highest, output(sim, "pump.P"));
    }
    EXPECT_LE(highest, 1.01 * 800.0);
    EXPECT_GT(output(sim, "pump.P"), 0.97 * 800.0) << "at its limit";
    std::printf("[ measured ] power limit 800 W: highest shaft power %.2f W\n", highest);
  }
}

// --- jacobians through the C ABI --------------------------------------------

struct Fixture {
  FakeNetwork net;
  FakeHost host{net, "x"};
  std::unique_ptr<Instance> instance;
};

TEST(LoadSensingJacobians, MatchCentralDifferences) {
  double worst = 0.0;
  {
    Fixture f;
    f.host.numbers = {{"max_displacement", 1e-5}, {"speed", 150},      {"margin", 2e6},
                      {"cutoff_pressure", 25e6},  {"max_power", 30e3}, {"leakage", 1e-12}};
    f.host.port_nodes = {{"P", "p"}, {"S", "s"}, {"LS", "ls"}};
    f.instance = std::make_unique<Instance>("variable-pump", f.host);
    ASSERT_EQ(f.instance->setup(), MH_OK) << f.host.all_logs();
    const int32_t p = f.host.port("P").index, s = f.host.port("S").index;
    const int32_t ls = f.host.port("LS").index, eps = f.host.states.at(0).index;
    for (const auto& v : std::vector<std::array<double, 4>>{{12e6, 1e5, 10e6, 0.3},
                                                            {11.99e6, 1e5, 10e6, 0.5},
                                                            {24.95e6, 1e5, 22.9e6, 0.9},
                                                            {20e6, 1e5, 19e6, 0.8},
                                                            {2e6, 1e5, 3e5, 0.2}}) {
      Evaluation e(f.net);
      e.y[p] = v[0];
      e.y[s] = v[1];
      e.y[ls] = v[2];
      e.y[eps] = v[3];
      worst = std::max(worst, jacobian_error(*f.instance, e));
    }
  }
  for (const char* compensation : {"pre", "post"}) {
    Fixture f;
    f.host.numbers = {{"flow_coefficient", 2e-8}, {"time_constant", 0.02}};
    f.host.tables["reference"] = {2u, {0, 5}};
    f.host.strings["compensation"] = compensation;
    f.host.port_nodes = {{"P", "p"}, {"T", "t"}, {"A", "a"}, {"B", "b"}, {"LS", "ls"}, {"X", "x"}};
    f.instance = std::make_unique<Instance>("ls-valve-section", f.host);
    ASSERT_EQ(f.instance->setup(), MH_OK) << f.host.all_logs();
    const auto idx = [&f](const char* k) { return f.host.port(k).index; };
    const int32_t u = f.host.states.at(0).index;
    for (const double spool : {5.0, 0.3, -0.2, -6.0}) {
      for (const double supply : {12e6, 10.5e6, 9e6}) {
        Evaluation e(f.net);
        e.y[idx("P")] = supply;
        e.y[idx("T")] = 1e5;
        e.y[idx("A")] = 10e6;
        e.y[idx("B")] = 3e6;
        e.y[idx("LS")] = 8e6;
        if (std::string(compensation) == "post") e.y[idx("X")] = 10.2e6;
        e.y[u] = spool;
        worst = std::max(worst, jacobian_error(*f.instance, e));
      }
    }
  }
  {
    Fixture f;
    f.host.port_nodes = {{"A", "a"}, {"B", "b"}, {"C", "c"}};
    f.instance = std::make_unique<Instance>("shuttle-valve", f.host);
    ASSERT_EQ(f.instance->setup(), MH_OK) << f.host.all_logs();
    const auto idx = [&f](const char* k) { return f.host.port(k).index; };
    for (const auto& v : std::vector<std::array<double, 3>>{
             {10e6, 5e6, 9e6}, {5e6, 5.005e6, 4e6}, {1e5, 8e6, 8.1e6}}) {
      Evaluation e(f.net);
      e.y[idx("A")] = v[0];
      e.y[idx("B")] = v[1];
      e.y[idx("C")] = v[2];
      worst = std::max(worst, jacobian_error(*f.instance, e));
    }
  }
  // 1e-5 would do for the limiters' rounded corners (curvature 1/w: the
  // differences' own truncation, 2e-6), but a post-compensated section shut
  // by its compensator (supply 1.2 MPa below p_X) depends on its far lower
  // load through two nested roundings: entries of 1e-18 beside 1e-9 in one
  // row, which central differences resolve to 2.4e-4 of the 1e-8 floor. A
  // wrong derivative is off by O(1).
  EXPECT_LT(worst, 5e-4);
  std::printf("[ measured ] load-sensing jacobians: max relative error %.3g\n", worst);
}

TEST(LoadSensingOptions, BadValuesAreRefusedOnTheirKey) {
  {
    Fixture f;
    f.host.numbers = {{"flow_coefficient", 2e-8}, {"time_constant", 0.02}};
    f.host.tables["reference"] = {2u, {0, 5}};
    f.host.strings["compensation"] = "sideways";
    f.host.port_nodes = {{"P", "p"}, {"T", "t"}, {"A", "a"}, {"B", "b"}, {"LS", "ls"}};
    Instance section("ls-valve-section", f.host);
    EXPECT_EQ(section.setup(), MH_ERROR);
    EXPECT_EQ(f.host.option_errors, std::vector<std::string>{"compensation"});
  }
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, double>>{{"max_displacement", 0.0},
                                                   {"margin", -1.0},
                                                   {"cutoff_pressure", -5.0},
                                                   {"max_power", 0.0},
                                                   {"initial_displacement", 1.5},
                                                   {"leakage", -1e-12}}) {
    Fixture f;
    f.host.numbers = {{"max_displacement", 1e-5}, {"speed", 150}, {"margin", 2e6}};
    f.host.numbers[key] = value;
    f.host.port_nodes = {{"P", "p"}, {"S", "s"}, {"LS", "ls"}};
    Instance pump("variable-pump", f.host);
    EXPECT_EQ(pump.setup(), MH_ERROR) << key;
    EXPECT_EQ(f.host.option_errors, std::vector<std::string>{key}) << key;
  }
}

}  // namespace
}  // namespace mh::test
