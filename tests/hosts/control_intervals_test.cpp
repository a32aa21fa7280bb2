// Control-signal intervals (hosts/monohydra/report/control_intervals.cpp):
// which columns are control signals (their declared role and range), and
// where their magnitude exceeds 1 % of that range.
#include "control_intervals.hpp"

#include <gtest/gtest.h>

#include "monohydra/host.h"
#include "synthetic_run.hpp"

namespace mh::test {
namespace {

VariableInfo control_signal(double lo, double hi) {
  VariableInfo v;
  v.role = MH_ROLE_CONTROL_SIGNAL;
  v.range_min = lo;
  v.range_max = hi;
  return v;
}

TEST(ControlIntervals, TheColumnsAreThoseDeclaredControlSignalsWithARange) {
  SyntheticRun s;
  const auto zero = [](size_t, double) { return 0.0; };
  s.states = {{"U", "V", zero, control_signal(-10.0, 10.0)},
              {"p1", "Pa", zero},                                 // no role
              {"no_range", "V", zero, control_signal(0.0, 0.0)},  // no scale: not shaded
              {"I", "A", zero, control_signal(-0.2, 0.5)}};
  const auto cols = cli::control_columns(s.make());
  ASSERT_EQ(cols.size(), 2u);
  EXPECT_EQ(cols[0].name, "U");
  EXPECT_DOUBLE_EQ(cols[0].threshold, 0.1);  // 1 % of 10 V
  EXPECT_EQ(cols[1].name, "I");
  EXPECT_DOUBLE_EQ(cols[1].threshold, 0.005);  // 1 % of the larger end, 0.5 A
}

TEST(ControlIntervals, OnWhileTheSignalExceedsOnePercentOfItsRange) {
  SyntheticRun s;
  s.rows = 101;
  s.dt = 0.1;  // t = 0 .. 10 s
  // The four-bar's reference: +10 V on [1, 2.5) s, -10 V on [5, 8) s; 0.1 V
  // exactly (not above the threshold) at t = 9 s.
  s.states = {{"U", "V",
               [](size_t k, double) {
                 if (k >= 10 && k < 25) return 10.0;
                 if (k >= 50 && k < 80) return -10.0;
                 return k == 90 ? 0.1 : 0.0;
               },
               control_signal(-10.0, 10.0)}};
  const cli::RunRecord run = s.make();
  const auto on = cli::control_on_intervals(run, cli::control_columns(run));
  ASSERT_EQ(on.size(), 2u);
  EXPECT_DOUBLE_EQ(on[0].begin, 1.0);
  EXPECT_DOUBLE_EQ(on[0].end, 2.4);
  EXPECT_DOUBLE_EQ(on[1].begin, 5.0);
  EXPECT_DOUBLE_EQ(on[1].end, 7.9);
}

TEST(ControlIntervals, SeveralSignalsShadeTheUnionOfTheirIntervals) {
  SyntheticRun s;
  s.states = {{"U1", "V", [](size_t k, double) { return k >= 2 && k <= 4 ? 5.0 : 0.0; },
               control_signal(-10.0, 10.0)},
              {"U2", "V", [](size_t k, double) { return k >= 4 && k <= 6 ? -5.0 : 0.0; },
               control_signal(-10.0, 10.0)}};
  const cli::RunRecord run = s.make();
  auto cols = cli::control_columns(run);
  cols.push_back({"absent", 1.0});  // a column the run lacks is ignored
  const auto on = cli::control_on_intervals(run, cols);
  ASSERT_EQ(on.size(), 1u);
  EXPECT_DOUBLE_EQ(on[0].begin, 0.2);
  EXPECT_DOUBLE_EQ(on[0].end, 0.6);
}

TEST(ControlIntervals, NoControlSignalNoInterval) {
  SyntheticRun s;
  const cli::RunRecord run = s.make();
  EXPECT_TRUE(cli::control_columns(run).empty());
  EXPECT_TRUE(cli::control_on_intervals(run, {}).empty());
}

}  // namespace
}  // namespace mh::test
