// Valve open intervals (hosts/monohydra/valve_intervals.cpp): which column is
// a valve's spool, and where |U| exceeds 1 % of its 10 V full scale.
#include "valve_intervals.hpp"

#include <gtest/gtest.h>

#include "synthetic_run.hpp"

namespace mh::test {
namespace {

ModelFile model_with_valves(const std::string& subsystems) {
  return parse_model_text(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - {name: rod, parent: ground, joint: {type: revolute}, mass: 1,"
      " shape: {type: beam, length: 1}}\n"
      "subsystems:\n" +
          subsystems,
      "valves.yaml");
}

TEST(ValveIntervals, TheSpoolColumnIsTheNamedStateElseTheQualifiedName) {
  const ModelFile file = model_with_valves(
      "  - {name: dcv, type: valve-4-3, states: {U: U}}\n"
      "  - {name: second, type: valve-4-3}\n"
      "  - {name: hidden, type: valve-4-3, states: {U: null}}\n"
      "  - {name: other, type: spring-damper, states: {U: spring_U}}\n");
  EXPECT_EQ(cli::valve_columns(file), (std::vector<std::string>{"U", "second.U"}));
}

TEST(ValveIntervals, OpenWhileTheSpoolExceedsOnePercentOfFullScale) {
  SyntheticRun s;
  s.rows = 101;
  s.dt = 0.1;  // t = 0 .. 10 s
  // The four-bar's reference: +10 V on [1, 2.5) s, -10 V on [5, 8) s; 0.1 V
  // exactly (not above the threshold) at t = 9 s.
  s.states = {{"U", "V", [](size_t k, double) {
                 if (k >= 10 && k < 25) return 10.0;
                 if (k >= 50 && k < 80) return -10.0;
                 return k == 90 ? 0.1 : 0.0;
               }}};
  const auto open = cli::valve_open_intervals(s.make(), {"U"});
  ASSERT_EQ(open.size(), 2u);
  EXPECT_DOUBLE_EQ(open[0].begin, 1.0);
  EXPECT_DOUBLE_EQ(open[0].end, 2.4);
  EXPECT_DOUBLE_EQ(open[1].begin, 5.0);
  EXPECT_DOUBLE_EQ(open[1].end, 7.9);
}

TEST(ValveIntervals, SeveralValvesShadeTheUnionOfTheirOpenIntervals) {
  SyntheticRun s;
  s.states = {{"U1", "V", [](size_t k, double) { return k >= 2 && k <= 4 ? 5.0 : 0.0; }},
              {"U2", "V", [](size_t k, double) { return k >= 4 && k <= 6 ? -5.0 : 0.0; }}};
  const auto open = cli::valve_open_intervals(s.make(), {"U1", "U2", "absent"});
  ASSERT_EQ(open.size(), 1u);
  EXPECT_DOUBLE_EQ(open[0].begin, 0.2);
  EXPECT_DOUBLE_EQ(open[0].end, 0.6);
}

TEST(ValveIntervals, NoValveNoInterval) {
  SyntheticRun s;
  EXPECT_TRUE(cli::valve_open_intervals(s.make(), {}).empty());
}

}  // namespace
}  // namespace mh::test
