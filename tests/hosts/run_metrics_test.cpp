// The table's numbers from a run's columns (hosts/monohydra/run_metrics.cpp),
// on runs built by hand so every expected value is known exactly.
#include "run_metrics.hpp"

#include <gtest/gtest.h>

#include "synthetic_run.hpp"

namespace mh::test {
namespace {

SyntheticRun three_steps() {
  SyntheticRun s;
  s.rows = 4;  // t = 0, 0.1, 0.2, 0.3: three steps
  s.z = {[](size_t k, double) { return 0.1 * static_cast<double>(k); }};
  s.iters = [](size_t k, double) { return k == 0 ? 0.0 : static_cast<double>(k); };  // 1, 2, 3
  s.wall = [](size_t k, double) { return k == 0 ? 0.5 : 0.1; };  // start 0.5 s, steps 0.1 s
  s.drift = [](size_t k, double) { return k == 2 ? -0.2 : 0.01; };
  s.W = [](size_t k, double) { return k == 3 ? -4.0 : 1.0; };
  s.phi = [](size_t k, double) { return 1e-12 * static_cast<double>(k); };
  return s;
}

TEST(RunMetrics, StepsAverageOverStepsAndWallTimeIncludesTheStart) {
  const cli::RunMetrics m = cli::compute_metrics(three_steps().make());
  EXPECT_EQ(m.steps, 3);
  EXPECT_DOUBLE_EQ(m.simulated_seconds, 0.3);
  EXPECT_DOUBLE_EQ(m.avg_iterations, 2.0);  // (1 + 2 + 3) / 3: the row of t = 0 is no step
  EXPECT_EQ(m.max_iterations, 3);
  EXPECT_DOUBLE_EQ(m.wall_seconds, 0.8);
  EXPECT_DOUBLE_EQ(m.seconds_per_step, 0.1);
  EXPECT_DOUBLE_EQ(m.real_time_factor, 0.3 / 0.8);
}

// The costliest single step, not only the average: its wall time and when.
TEST(RunMetrics, TheWorstStepIsTheCostliestRowPerStepItStandsFor) {
  SyntheticRun s = three_steps();
  s.wall = [](size_t k, double) { return k == 0 ? 0.5 : k == 2 ? 0.25 : 0.1; };
  const cli::RunMetrics m = cli::compute_metrics(s.make());
  EXPECT_DOUBLE_EQ(m.worst_step_seconds, 0.25);
  EXPECT_DOUBLE_EQ(m.worst_step_time, 0.2);
  EXPECT_DOUBLE_EQ(m.seconds_per_step, 0.45 / 3.0);  // the average hides it
}

TEST(RunMetrics, DriftIsThePeakMagnitudeAndItsPercentIsOfTheLargestWork) {
  const cli::RunMetrics m = cli::compute_metrics(three_steps().make());
  EXPECT_DOUBLE_EQ(m.peak_abs_drift, 0.2);
  EXPECT_DOUBLE_EQ(m.peak_drift_time, 0.2);
  EXPECT_DOUBLE_EQ(m.max_abs_work, 4.0);  // |W| of a negative work counts
  ASSERT_TRUE(m.drift_percent.has_value());
  EXPECT_DOUBLE_EQ(*m.drift_percent, 5.0);
  EXPECT_DOUBLE_EQ(m.max_phi_norm, 3e-12);
}

TEST(RunMetrics, DriftPercentIsAbsentWithoutWork) {
  SyntheticRun s = three_steps();
  s.W = nullptr;
  EXPECT_FALSE(cli::compute_metrics(s.make()).drift_percent.has_value());
}

TEST(RunMetrics, ARunWithoutRowsHasZeros) {
  cli::RunRecord r;
  r.failed = true;
  const cli::RunMetrics m = cli::compute_metrics(r);
  EXPECT_EQ(m.steps, 0);
  EXPECT_EQ(m.wall_seconds, 0.0);
}

TEST(RunMetrics, PressuresAreTheWrittenStatesInPascal) {
  SyntheticRun s;
  s.states = {{"p1", "Pa", nullptr}, {"U", "V", nullptr}, {"p3", "Pa", nullptr}};
  s.outputs = {{"p_out", "Pa", nullptr}};  // an output in Pa is no state
  EXPECT_EQ(cli::pressure_columns(s.make()), (std::vector<std::string>{"p1", "p3"}));
}

TEST(RunMetrics, DifferencesAreTheLargestOverTheRowsBothRunsHave) {
  SyntheticRun a;
  a.rows = 6;
  a.z = {[](size_t, double) { return 0.0; }, [](size_t, double t) { return t; }};
  a.states = {{"p2", "Pa", [](size_t, double) { return 1e6; }}};
  SyntheticRun b = a;
  b.rows = 4;  // failed after three steps
  b.z[1] = [](size_t k, double t) { return t + (k == 3 ? 0.25 : 0.0); };
  b.states[0].value = [](size_t k, double) { return 1e6 - 50.0 * static_cast<double>(k); };
  const cli::Differences d = cli::differences(b.make(), a.make(), {"p2", "p9"});
  EXPECT_EQ(d.rows, 4);
  ASSERT_TRUE(d.max_abs_z.has_value());
  EXPECT_DOUBLE_EQ(*d.max_abs_z, 0.25);
  ASSERT_EQ(d.pressures.size(), 2u);
  ASSERT_TRUE(d.pressures[0].has_value());
  EXPECT_DOUBLE_EQ(*d.pressures[0], 150.0);
  EXPECT_FALSE(d.pressures[1].has_value());  // no such column
}

TEST(RunMetrics, DifferencesRefuseRunsAtOtherTimes) {
  SyntheticRun a;
  SyntheticRun b = a;
  b.dt = 0.05;
  EXPECT_THROW(cli::differences(b.make(), a.make(), {}), std::invalid_argument);
}

}  // namespace
}  // namespace mh::test
