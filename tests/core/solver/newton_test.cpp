// The one Newton iteration (core/src/solver/newton.hpp) on problems with
// closed-form answers: its convergence, its accounting of iterations, and
// each way it ends.
#include "../../../core/src/solver/newton.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace {

// F(u) = g(u) componentwise with g' given, increments measured against a
// tolerance `tol`: a scalar problem when u has one entry.
class Componentwise : public mh::NewtonProblem {
 public:
  Componentwise(Eigen::VectorXd u0, std::function<double(double)> g,
                std::function<double(double)> dg, double tol)
      : u(std::move(u0)), g_(std::move(g)), dg_(std::move(dg)), tol_(tol) {}
  void residual(Eigen::VectorXd& f) override {
    ++residuals;
    for (Eigen::Index i = 0; i < u.size(); ++i) f[i] = g_(u[i]);
  }
  bool needs_setup() override { return !keep_first_tangent || setups == 0; }
  void setup() override {
    ++setups;
    slope = u.unaryExpr(dg_);
  }
  void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
    du = -f.cwiseQuotient(slope);
  }
  void add(const Eigen::VectorXd& du) override { u += du; }
  void subtract(const Eigen::VectorXd& du) override { u -= du; }
  double measure(const Eigen::VectorXd& du, int& worst) override {
    Eigen::Index i = 0;
    const double size = du.cwiseAbs().maxCoeff(&i) / tol_;
    worst = static_cast<int>(i);
    return size;
  }
  // With undo_growth, an increment larger than the last kept one is refused.
  bool keep(double size) override {
    if (undo_growth && last_ > 0.0 && size > last_) return false;
    last_ = size;
    return true;
  }
  bool stop_early(int iteration) override { return stop_after > 0 && iteration + 1 >= stop_after; }

  Eigen::VectorXd u, slope;
  int residuals = 0, setups = 0, stop_after = 0;
  bool keep_first_tangent = false, undo_growth = false;

 private:
  std::function<double(double)> g_, dg_;
  double tol_;
  double last_ = 0.0;
};

Eigen::VectorXd one(double v) {
  return Eigen::VectorXd::Constant(1, v);
}

TEST(NewtonIteration, ConvergesQuadraticallyToTheSquareRootOfTwo) {
  Componentwise p(
      one(1.0), [](double x) { return x * x - 2.0; }, [](double x) { return 2.0 * x; }, 1e-12);
  Eigen::VectorXd f(1), du(1);
  const mh::NewtonOutcome out = mh::newton_iterate(p, 20, f, du);
  ASSERT_EQ(out.end, mh::NewtonOutcome::End::converged);
  EXPECT_NEAR(p.u[0], std::sqrt(2.0), 1e-15);
  // From 1: increments 0.5, 0.083, 2.5e-3, 2.1e-6, 1.6e-12, then round-off.
  EXPECT_EQ(out.iterations, 6);
  // One residual before the first increment and one after each.
  EXPECT_EQ(p.residuals, out.iterations + 1);
  EXPECT_EQ(p.setups, out.iterations);
}

TEST(NewtonIteration, AKeptTangentConvergesLinearlyInMoreIterations) {
  Componentwise full(
      one(1.0), [](double x) { return x * x - 2.0; }, [](double x) { return 2.0 * x; }, 1e-10);
  Componentwise chord = full;
  chord.keep_first_tangent = true;
  Eigen::VectorXd f(1), du(1);
  const mh::NewtonOutcome a = mh::newton_iterate(full, 50, f, du);
  const mh::NewtonOutcome b = mh::newton_iterate(chord, 50, f, du);
  ASSERT_EQ(b.end, mh::NewtonOutcome::End::converged);
  EXPECT_EQ(chord.setups, 1);
  // The chord contracts at |1 - sqrt(2)/1| = 0.41 per iteration.
  EXPECT_GT(b.iterations, 2 * a.iterations);
  EXPECT_NEAR(chord.u[0], std::sqrt(2.0), 1e-9);
}

TEST(NewtonIteration, ANonFiniteResidualIsReportedWithItsRow) {
  Componentwise p(
      Eigen::Vector3d(1.0, -1.0, 2.0), [](double x) { return std::log(x); },
      [](double x) { return 1.0 / x; }, 1e-12);
  Eigen::VectorXd f(3), du(3);
  const mh::NewtonOutcome out = mh::newton_iterate(p, 20, f, du);
  ASSERT_EQ(out.end, mh::NewtonOutcome::End::not_finite);
  EXPECT_EQ(out.row, 1);
  EXPECT_EQ(out.iterations, 0);
}

TEST(NewtonIteration, ACycleEndsAtTheIterationLimitWithItsLastIncrement) {
  // x^3 - 2x + 2 from 0: Newton cycles 0, 1, 0, 1, ... with increments of 1.
  Componentwise p(
      one(0.0), [](double x) { return x * x * x - 2.0 * x + 2.0; },
      [](double x) { return 3.0 * x * x - 2.0; }, 1e-8);
  Eigen::VectorXd f(1), du(1);
  const mh::NewtonOutcome out = mh::newton_iterate(p, 7, f, du);
  ASSERT_EQ(out.end, mh::NewtonOutcome::End::not_converged);
  EXPECT_EQ(out.iterations, 7);
  EXPECT_NEAR(out.size, 1e8, 1.0);
  EXPECT_EQ(p.u[0], 1.0);  // seven increments of the cycle from 0
}

TEST(NewtonIteration, AnIncrementTheProblemRefusesIsUndoneAndNotEvaluated) {
  Componentwise p(
      one(3.0), [](double x) { return std::atan(x); }, [](double x) { return 1.0 / (1.0 + x * x); },
      1e-8);
  p.undo_growth = true;
  Eigen::VectorXd f(1), du(1);
  const mh::NewtonOutcome out = mh::newton_iterate(p, 4, f, du);
  // atan from 3 diverges: the first increment (-13.5) is kept, the second
  // (larger) undone, and so on: the iterate stays where the first left it.
  EXPECT_EQ(out.end, mh::NewtonOutcome::End::not_converged);
  EXPECT_EQ(out.iterations, 4);
  EXPECT_NEAR(p.u[0], 3.0 - std::atan(3.0) * 10.0, 1e-12);
  EXPECT_EQ(p.residuals, 2);  // at the start and after the one kept increment
}

TEST(NewtonIteration, StopEarlyAcceptsTheIterateUnconverged) {
  Componentwise p(
      one(1.0), [](double x) { return x * x - 2.0; }, [](double x) { return 2.0 * x; }, 1e-12);
  p.stop_after = 2;
  Eigen::VectorXd f(1), du(1);
  const mh::NewtonOutcome out = mh::newton_iterate(p, 20, f, du);
  EXPECT_EQ(out.end, mh::NewtonOutcome::End::stopped);
  EXPECT_EQ(out.iterations, 2);
  EXPECT_NEAR(p.u[0], 17.0 / 12.0, 1e-15);  // 1 -> 3/2 -> 17/12
  EXPECT_GT(out.size, 1.0);
}

// Damping (NewtonDamping): atan(x) from 3, where Newton's first increment
// lands at -9.5 and the iteration diverges, converges once the increments
// are shortened until the simplified increment shrinks.
TEST(NewtonDamping, ShortensTheIncrementsOfADivergingIterationUntilItConverges) {
  const auto atan_problem = [] {
    return Componentwise(
        one(3.0), [](double x) { return std::atan(x); },
        [](double x) { return 1.0 / (1.0 + x * x); }, 1e-12);
  };
  Eigen::VectorXd f(1), du(1), trial(1), correction(1);
  Componentwise plain = atan_problem();
  EXPECT_NE(mh::newton_iterate(plain, 30, f, du).end, mh::NewtonOutcome::End::converged);
  Componentwise damped = atan_problem();
  mh::NewtonDamping damping{trial, correction};
  const mh::NewtonOutcome out = mh::newton_iterate(damped, 30, f, du, &damping);
  ASSERT_EQ(out.end, mh::NewtonOutcome::End::converged);
  EXPECT_NEAR(damped.u[0], 0.0, 1e-12);
  // lambda = 1 and 1/2 fail the test (simplified increments 14.6 and 12.7
  // against 0.75 and 0.875 of 12.5); 1/4 passes.
  EXPECT_EQ(out.smallest_factor, 0.25);
  EXPECT_EQ(out.damped, 1);
}

// x^3 - 2x + 2 from 0, where plain Newton cycles 0, 1, 0, ... to its limit
// (above): damped, the iteration leaves the cycle and stops, saying so, at
// the local minimum of |F| near sqrt(2/3), where F = 0.91 and F' = 0: no
// shorter step decreases it, and the real root (-1.77) lies beyond.
TEST(NewtonDamping, StopsAtALocalMinimumOfTheResidualInsteadOfCycling) {
  Componentwise p(
      one(0.0), [](double x) { return x * x * x - 2.0 * x + 2.0; },
      [](double x) { return 3.0 * x * x - 2.0; }, 1e-12);
  Eigen::VectorXd f(1), du(1), trial(1), correction(1);
  mh::NewtonDamping damping{trial, correction};
  const mh::NewtonOutcome out = mh::newton_iterate(p, 50, f, du, &damping);
  EXPECT_EQ(out.end, mh::NewtonOutcome::End::no_descent);
  EXPECT_NEAR(p.u[0], std::sqrt(2.0 / 3.0), 0.01);
  EXPECT_LT(out.iterations, 10);
  EXPECT_GT(out.damped, 0);
}

TEST(NewtonDamping, AJacobianOfTheWrongSignEndsWithNoDescentAtTheIterateItStarted) {
  // F(x) = x with dF/dx given as -1: every increment points away from 0.
  Componentwise p(
      one(1.0), [](double x) { return x; }, [](double) { return -1.0; }, 1e-8);
  Eigen::VectorXd f(1), du(1), trial(1), correction(1);
  mh::NewtonDamping damping{trial, correction};
  const mh::NewtonOutcome out = mh::newton_iterate(p, 20, f, du, &damping);
  EXPECT_EQ(out.end, mh::NewtonOutcome::End::no_descent);
  EXPECT_EQ(p.u[0], 1.0);
  EXPECT_EQ(out.iterations, 0);
  // 1, 1/2, ... 1/1024: eleven trials, each with its residual.
  EXPECT_EQ(p.residuals, 1 + 11);
}

}  // namespace
