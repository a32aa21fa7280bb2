// When Newton's iterate counts as converged (core/include/monohydra/core/
// tangent_reuse.hpp), fed the increments of iterations whose contraction
// rates are known: an exact tangent's quadratic contraction stops at the
// tolerance, a linear one on tangents made in the step (a wrong Jacobian)
// only where its error bound is far below it, and a factorization kept from
// earlier steps (modified Newton) at its error bound.
#include "monohydra/core/tangent_reuse.hpp"

#include <gtest/gtest.h>

namespace mh {
namespace {

mh_step_coefficients coefficients() {
  mh_step_coefficients c{};
  c.struct_size = sizeof(c);
  c.dxd_dx_second = 200.0;
  c.dxdd_dx_second = 40000.0;
  c.dxd_dx_first = 200.0;
  return c;
}

// One step of `reuse`: increments of `first` times the tolerance shrinking by
// `rate` each iteration, a tangent factored wherever it asks for one, until
// converged() or `limit` iterations. The iterations it took (limit + 1: none
// converged).
int iterations_to_converge(TangentReuse& reuse, double first, double rate, int limit = 40) {
  const mh_step_coefficients c = coefficients();
  reuse.begin_step();
  double worst = first;
  for (int i = 1; i <= limit; ++i) {
    if (reuse.needs_tangent(c)) reuse.factored(c);
    reuse.increment(worst);
    if (reuse.converged(worst)) return i;
    worst *= rate;
  }
  return limit + 1;
}

TEST(TangentReuse, FullNewtonContractingQuadraticallyConvergesAtTheTolerance) {
  TangentReuse reuse;
  reuse.set_mode(TangentReuse::Mode::full);
  const mh_step_coefficients c = coefficients();
  reuse.begin_step();
  int i = 0;
  for (const double worst : {300.0, 3.0, 3e-4}) {  // each the square of the last, scaled
    ++i;
    if (reuse.needs_tangent(c)) reuse.factored(c);
    reuse.increment(worst);
    if (reuse.converged(worst)) break;
  }
  EXPECT_EQ(i, 3);
  EXPECT_FALSE(reuse.tangent_suspect());
}

// A rate of 0.4 on fresh tangents: an increment of half the tolerance
// leaves two thirds of it, and the trapezoidal rule's rates carry that on.
// It converges once theta / (1 - theta) |dx| is 1e-4 of the tolerance.
TEST(TangentReuse, FullNewtonContractingLinearlyIsHeldToItsErrorBound) {
  TangentReuse reuse;
  reuse.set_mode(TangentReuse::Mode::full);
  const int its = iterations_to_converge(reuse, 50.0, 0.4);
  EXPECT_TRUE(reuse.tangent_suspect());
  // 50 * 0.4^(i-1) * 0.4 / 0.6 <= 1e-4 first at i = 15; at the tolerance
  // alone it would have stopped at i = 6 (50 * 0.4^5 = 0.512).
  EXPECT_EQ(its, 15);
}

TEST(TangentReuse, PerStepNewtonsChordContractingLinearlyIsHeldToItsErrorBound) {
  TangentReuse reuse;
  reuse.set_mode(TangentReuse::Mode::per_step);
  EXPECT_GT(iterations_to_converge(reuse, 50.0, 0.4), 6);
  EXPECT_TRUE(reuse.tangent_suspect());
}

TEST(TangentReuse, PerStepNewtonsFastChordConvergesAtTheTolerance) {
  TangentReuse reuse;
  reuse.set_mode(TangentReuse::Mode::per_step);
  EXPECT_EQ(iterations_to_converge(reuse, 50.0, 1e-3), 2);
  EXPECT_FALSE(reuse.tangent_suspect());
}

// Modified Newton keeps a factorization from an earlier step: its chord
// contracts linearly by design, and its bound is the tolerance itself.
TEST(TangentReuse, ModifiedNewtonOnAKeptFactorizationConvergesAtItsErrorBound) {
  TangentReuse reuse;
  reuse.set_mode(TangentReuse::Mode::modified);
  (void)iterations_to_converge(reuse, 2.0, 0.01);  // factors once, in this step
  // The next step runs on that factorization: 10 * 0.4^3 = 0.64, bound 0.43.
  EXPECT_EQ(iterations_to_converge(reuse, 10.0, 0.4), 4);
  EXPECT_FALSE(reuse.tangent_suspect());
}

}  // namespace
}  // namespace mh
