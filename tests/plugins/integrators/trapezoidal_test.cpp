// The trapezoidal rule (Eqs. 32-34): the formulas to the last bit, and no
// numerical dissipation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "problems.hpp"

namespace mh_test {
namespace {

// One step's map is Eqs. (33)-(34) and the predictors after Eq. (34), written
// in the 1.x code's form and order, to the last bit.
TEST(Trapezoidal, OneStepMapEqualsEqs33And34ToTheLastBit) {
  Integrator integ("trapezoidal");
  ASSERT_EQ(integ.setup({MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_FIRST_ORDER, MH_UNKNOWN_ALGEBRAIC},
                        0.0, 1e-3),
            MH_OK);
  const std::vector<double> x{0.3172, 1.37e7, 5.5}, xd{-1.713, -4.1e5, 0.0}, xdd{29.03, 0.0, 0.0};
  ASSERT_EQ(integ.restart(0.25, x, xd, xdd), MH_OK);
  const double dt = 7.3e-4;  // not the run's dt: a shortened step
  ASSERT_EQ(integ.begin_step(0.25 + dt, dt), MH_OK);
  const mh_step_coefficients& c = integ.map.coefficients;
  EXPECT_EQ(c.h, dt);
  EXPECT_EQ(c.dxd_dx_second, 2.0 / dt);
  EXPECT_EQ(c.dxdd_dx_second, 4.0 / (dt * dt));
  EXPECT_EQ(c.dxd_dx_first, 2.0 / dt);
  // Position: predictor, zd_hat, zdd_hat.
  EXPECT_EQ(integ.x_predicted[0], x[0] + dt * xd[0] + (0.5 * dt * dt) * xdd[0]);
  EXPECT_EQ(integ.xd_offset[0], -((2.0 / dt) * x[0] + xd[0]));
  EXPECT_EQ(integ.xdd_offset[0], -((4.0 / (dt * dt)) * x[0] + (4.0 / dt) * xd[0] + xdd[0]));
  // Pressure: predictor, p_hat.
  EXPECT_EQ(integ.x_predicted[1], x[1] + dt * xd[1]);
  EXPECT_EQ(integ.xd_offset[1], -((2.0 / dt) * x[1] + xd[1]));
  // Algebraic: the last value, no offsets.
  EXPECT_EQ(integ.x_predicted[2], x[2]);
  EXPECT_EQ(integ.xd_offset[2], 0.0);
  EXPECT_EQ(integ.xdd_offset[2], 0.0);

  // Accepting the map's own rates makes them the next step's history.
  const std::vector<double> x1{0.3171, 1.36e7, 5.4};
  const std::vector<double> xd1{(2.0 / dt) * x1[0] + integ.xd_offset[0],
                                (2.0 / dt) * x1[1] + integ.xd_offset[1], 0.0};
  const std::vector<double> xdd1{(4.0 / (dt * dt)) * x1[0] + integ.xdd_offset[0], 0.0, 0.0};
  ASSERT_EQ(integ.accept(0.25 + dt, x1, xd1, xdd1), MH_OK);
  const double h = 1e-3;
  ASSERT_EQ(integ.begin_step(0.25 + dt + h, h), MH_OK);
  EXPECT_EQ(integ.x_predicted[0], x1[0] + h * xd1[0] + (0.5 * h * h) * xdd1[0]);
  EXPECT_EQ(integ.xd_offset[0], -((2.0 / h) * x1[0] + xd1[0]));
  EXPECT_EQ(integ.xdd_offset[0], -((4.0 / (h * h)) * x1[0] + (4.0 / h) * xd1[0] + xdd1[0]));
  EXPECT_EQ(integ.x_predicted[1], x1[1] + h * xd1[1]);
  EXPECT_EQ(integ.xd_offset[1], -((2.0 / h) * x1[1] + xd1[1]));
  EXPECT_EQ(integ.x_predicted[2], x1[2]);
}

// x'' + x = 0: the trapezoidal rule keeps E = (xd^2 + x^2) / 2 exactly, so
// over 1e4 steps of h = 0.1 (159 periods) it drifts by round-off only: the
// bound is 1e4 steps x 1e-15 (a few ulps a step), where a dissipative method
// loses orders of magnitude more (GeneralizedAlpha.DissipatesBelowRhoInfOne).
TEST(Trapezoidal, ConservesTheUndampedOscillatorsEnergyToRoundOffOver1e4Steps) {
  const LinearProblem p{
      {MH_UNKNOWN_SECOND_ORDER}, {1.0}, {0.0}, {1.0}, [](double, double* f) { f[0] = 0.0; }};
  const State s0{0.0, {1.0}, {0.0}, {-1.0}};
  const double e0 = 0.5;
  double worst = 0.0;
  Integrator integ("trapezoidal");
  run(integ, p, s0, uniform_steps(1000.0, 0.1), [&](const State& s) {
    const double e = 0.5 * (s.xd[0] * s.xd[0] + s.x[0] * s.x[0]);
    worst = std::max(worst, std::abs(e - e0) / e0);
  });
  std::printf("  trapezoidal: max |E - E0| / E0 over 1e4 steps = %.3e\n", worst);
  EXPECT_LE(worst, 1e4 * 1e-15);
}

}  // namespace
}  // namespace mh_test
