// BDF2: strong damping of stiff components, second order with step changes,
// backward Euler right after a restart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "problems.hpp"

namespace mh_test {
namespace {

// y' = lambda y at h lambda = -1e6: |y_{n+1} / y_n| after the first (backward
// Euler) step, and per step over the next ten BDF2 steps (geometric mean: the
// roots are a complex pair, so single-step ratios swing).
TEST(Bdf2, DampsTheStiffComponentToBelowOnePercentPerStep) {
  const double lambda = -1e6;
  const LinearProblem p{
      {MH_UNKNOWN_FIRST_ORDER}, {0.0}, {1.0}, {-lambda}, [](double, double* f) { f[0] = 0.0; }};
  std::vector<double> y{1.0};
  Integrator integ("bdf2");
  run(integ, p, State{0.0, {1.0}, {lambda}, {0.0}}, std::vector<double>(11, 1.0),
      [&](const State& s) { y.push_back(s.x[0]); });
  const double first = std::abs(y[1] / y[0]);
  const double per_step = std::pow(std::abs(y[11] / y[1]), 0.1);
  std::printf("  bdf2 at h lambda = -1e6: |amplification| first step %.3e, BDF2 steps %.3e\n",
              first, per_step);
  EXPECT_LT(first, 0.01);
  EXPECT_LT(per_step, 0.01);
}

// Steps alternating h and 2h (the variable-step coefficients every step):
// halving both still divides the error by 4.
TEST(Bdf2, IsSecondOrderWithStepSizeChanges) {
  const auto steps = [](double h) {
    std::vector<double> hs;
    double t = 0.0;
    for (size_t i = 0; t < 2.0 - 1e-12; ++i) {
      hs.push_back(i % 2 == 0 ? h : 2.0 * h);
      t += hs.back();
    }
    return hs;
  };
  const DampedOscillator o;
  const FirstOrder q;
  double e_osc[2] = {0.0, 0.0}, e_first[2] = {0.0, 0.0};
  const double hs[2] = {0.01, 0.005};
  for (int k = 0; k < 2; ++k) {
    Integrator a("bdf2"), b("bdf2");
    run(a, o.problem(), o.initial(), steps(hs[k]),
        [&](const State& s) { e_osc[k] = std::max(e_osc[k], std::abs(s.x[0] - o.x(s.t))); });
    run(b, q.problem(), q.initial(), steps(hs[k]),
        [&](const State& s) { e_first[k] = std::max(e_first[k], std::abs(s.x[0] - q.y(s.t))); });
  }
  std::printf(
      "  bdf2 steps h, 2h, h, ...: oscillator %.3e / %.3e = %.3f, first order %.3e / %.3e = %.3f\n",
      e_osc[0], e_osc[1], e_osc[0] / e_osc[1], e_first[0], e_first[1], e_first[0] / e_first[1]);
  EXPECT_GE(e_osc[0] / e_osc[1], 3.5);
  EXPECT_LE(e_osc[0] / e_osc[1], 4.5);
  EXPECT_GE(e_first[0] / e_first[1], 3.5);
  EXPECT_LE(e_first[0] / e_first[1], 4.5);
}

// After a restart the history is the given state alone: the step is backward
// Euler on both levels, xd = (x - x_n) / h, xdd = (xd - xd_n) / h; the step
// after it is BDF2 (dxd/dx = 3 / (2h) at a constant step).
TEST(Bdf2, FirstStepAfterARestartIsBackwardEuler) {
  Integrator integ("bdf2");
  ASSERT_EQ(integ.setup({MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_FIRST_ORDER}, 0.0, 0.1), MH_OK);
  ASSERT_EQ(integ.restart(0.0, {9.0, 9.0}, {9.0, 9.0}, {9.0, 0.0}), MH_OK);
  for (int i = 1; i <= 3; ++i) {  // some history to forget
    ASSERT_EQ(integ.begin_step(0.1 * i, 0.1), MH_OK);
    ASSERT_EQ(integ.accept(0.1 * i, {1.0 * i, 2.0 * i}, {3.0 * i, 4.0 * i}, {5.0 * i, 0.0}), MH_OK);
  }
  const std::vector<double> x{0.4, -2.0}, xd{1.1, 0.6}, xdd{-3.0, 0.0};
  ASSERT_EQ(integ.restart(0.5, x, xd, xdd), MH_OK);
  const double h = 0.02;
  ASSERT_EQ(integ.begin_step(0.5 + h, h), MH_OK);
  const double tol = 1e-14;
  EXPECT_NEAR(integ.map.coefficients.dxd_dx_second, 1.0 / h, tol / h);
  EXPECT_NEAR(integ.map.coefficients.dxdd_dx_second, 1.0 / (h * h), tol / (h * h));
  EXPECT_NEAR(integ.map.coefficients.dxd_dx_first, 1.0 / h, tol / h);
  // The map's rates at an arbitrary x equal backward Euler's.
  const std::vector<double> x1{0.43, -1.9};
  for (size_t i = 0; i < 2; ++i) {
    const double be_xd = (x1[i] - x[i]) / h;
    EXPECT_NEAR(integ.xd_at(i, x1[i]), be_xd, tol * (std::abs(x1[i]) + std::abs(x[i])) / h);
  }
  const double be_xdd = ((x1[0] - x[0]) / h - xd[0]) / h;
  EXPECT_NEAR(integ.xdd_at(0, x1[0]), be_xdd, 1e-12 * std::abs(be_xdd) + 1e-9);

  ASSERT_EQ(integ.accept(0.5 + h, x1, {integ.xd_at(0, x1[0]), integ.xd_at(1, x1[1])},
                         {integ.xdd_at(0, x1[0]), 0.0}),
            MH_OK);
  ASSERT_EQ(integ.begin_step(0.5 + 2 * h, h), MH_OK);
  EXPECT_NEAR(integ.map.coefficients.dxd_dx_second, 1.5 / h, tol / h);
}

}  // namespace
}  // namespace mh_test
