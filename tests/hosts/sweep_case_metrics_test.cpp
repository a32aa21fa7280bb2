// A case's error against a reference run: exact for what linear
// interpolation reproduces, the true maximum for a known difference, and
// none when the reference does not cover the run.
#include <gtest/gtest.h>

#include <cmath>

#include "case_metrics.hpp"

namespace mh::cli::sweep {
namespace {

ReferenceRun reference(double dt, double t_end, double (*f)(double)) {
  ReferenceRun r;
  std::vector<double> x;
  for (int k = 0; k * dt <= t_end + 1e-12; ++k) {
    r.t.push_back(k * dt);
    x.push_back(f(k * dt));
  }
  r.columns["x"] = x;
  return r;
}

TEST(SweepCaseMetrics, ALinearReferenceIsInterpolatedExactlyBetweenItsRows) {
  const ReferenceRun ref = reference(0.1, 1.0, [](double t) { return 3.0 * t - 1.0; });
  std::vector<double> t, x;
  for (double s = 0.0; s <= 1.0; s += 0.03) {
    t.push_back(s);
    x.push_back(3.0 * s - 1.0);
  }
  const auto e = max_abs_error(t, x, ref, "x");
  ASSERT_TRUE(e.has_value());
  EXPECT_LT(*e, 1e-14);
}

TEST(SweepCaseMetrics, TheErrorIsTheLargestDifferenceOverTheRunsRows) {
  // A fine reference of sin; the run is sin + 0.01 t^2: error 0.01 at t = 1,
  // plus at most the interpolation error of sin between 1e-4 s rows (~1e-9).
  const ReferenceRun ref = reference(1e-4, 1.0, [](double t) { return std::sin(t); });
  std::vector<double> t, x;
  for (int k = 0; k <= 100; ++k) {
    t.push_back(k * 0.01);
    x.push_back(std::sin(k * 0.01) + 0.01 * (k * 0.01) * (k * 0.01));
  }
  const auto e = max_abs_error(t, x, ref, "x");
  ASSERT_TRUE(e.has_value());
  EXPECT_NEAR(*e, 0.01, 1e-8);
}

TEST(SweepCaseMetrics, AReferenceThatEndsEarlyOrLacksTheColumnGivesNoError) {
  const ReferenceRun ref = reference(0.1, 0.5, [](double t) { return t; });
  EXPECT_FALSE(max_abs_error({0.0, 1.0}, {0.0, 1.0}, ref, "x").has_value());
  EXPECT_FALSE(max_abs_error({0.0, 0.5}, {0.0, 0.5}, ref, "y").has_value());
}

}  // namespace
}  // namespace mh::cli::sweep
