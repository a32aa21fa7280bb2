// Every integrator of the library is second order: the error against the
// closed-form solution falls by 4 when h halves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "problems.hpp"

namespace mh_test {
namespace {

constexpr double kEnd = 2.0;

double oscillator_error(const Case& c, double h) {
  const DampedOscillator o;
  Integrator integ(c.id, c.options);
  double worst = 0.0;
  run(integ, o.problem(), o.initial(), uniform_steps(kEnd, h),
      [&](const State& s) { worst = std::max(worst, std::abs(s.x[0] - o.x(s.t))); });
  return worst;
}

double first_order_error(const Case& c, double h) {
  const FirstOrder q;
  Integrator integ(c.id, c.options);
  double worst = 0.0;
  run(integ, q.problem(), q.initial(), uniform_steps(kEnd, h),
      [&](const State& s) { worst = std::max(worst, std::abs(s.x[0] - q.y(s.t))); });
  return worst;
}

TEST(Convergence, EveryIntegratorIsSecondOrderOnTheDampedOscillator) {
  for (const Case& c : all_cases()) {
    const double e1 = oscillator_error(c, 0.01), e2 = oscillator_error(c, 0.005);
    std::printf("  oscillator %-24s max|x - x_exact|: h=0.01 %.3e, h=0.005 %.3e, ratio %.3f\n",
                name(c).c_str(), e1, e2, e1 / e2);
    EXPECT_GE(e1 / e2, 3.5) << name(c);
    EXPECT_LE(e1 / e2, 4.5) << name(c);
  }
}

TEST(Convergence, EveryIntegratorIsSecondOrderOnTheFirstOrderProblem) {
  for (const Case& c : all_cases()) {
    const double e1 = first_order_error(c, 0.01), e2 = first_order_error(c, 0.005);
    std::printf("  first order %-23s max|y - y_exact|: h=0.01 %.3e, h=0.005 %.3e, ratio %.3f\n",
                name(c).c_str(), e1, e2, e1 / e2);
    EXPECT_GE(e1 / e2, 3.5) << name(c);
    EXPECT_LE(e1 / e2, 4.5) << name(c);
  }
}

// Unknowns (x second order, y first order, z algebraic) with z - x - y = 0:
// z holds the constraint at every step to round-off, and all three converge
// at order 2.
TEST(Convergence, EveryIntegratorIsSecondOrderOnAMixedSystemWithAnAlgebraicUnknown) {
  const Mixed mixed;
  for (const Case& c : all_cases()) {
    double errors[2] = {0.0, 0.0};
    const double hs[2] = {0.01, 0.005};
    for (int k = 0; k < 2; ++k) {
      Integrator integ(c.id, c.options);
      double worst_constraint = 0.0;
      run(integ, mixed.problem(), mixed.initial(), uniform_steps(kEnd, hs[k]), [&](const State& s) {
        const double x = mixed.osc.x(s.t), y = mixed.first.y(s.t);
        errors[k] = std::max(
            {errors[k], std::abs(s.x[0] - x), std::abs(s.x[1] - y), std::abs(s.x[2] - (x + y))});
        worst_constraint = std::max(worst_constraint, std::abs(s.x[2] - s.x[0] - s.x[1]));
        // Algebraic unknowns: the map's offsets are 0 and its prediction the last value.
        EXPECT_EQ(integ.xd_offset[2], 0.0);
        EXPECT_EQ(integ.xdd_offset[2], 0.0);
      });
      EXPECT_LE(worst_constraint, 1e-14) << name(c);
    }
    std::printf("  mixed %-29s max error: h=0.01 %.3e, h=0.005 %.3e, ratio %.3f\n", name(c).c_str(),
                errors[0], errors[1], errors[0] / errors[1]);
    EXPECT_GE(errors[0] / errors[1], 3.5) << name(c);
    EXPECT_LE(errors[0] / errors[1], 4.5) << name(c);
  }
}

}  // namespace
}  // namespace mh_test
