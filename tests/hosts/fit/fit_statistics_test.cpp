// The statistics of a fit (hosts/monohydra/fit/fit_statistics.cpp) against
// the closed form of a straight line's least squares, and the parameters the
// data cannot determine named as such.
#include "fit_statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

// y = a + b t sampled at t = 0..n-1 with noise sigma: J = [1 t] / sigma.
Eigen::MatrixXd line_jacobian(int n, double sigma) {
  Eigen::MatrixXd J(n, 2);
  for (int i = 0; i < n; ++i) J.row(i) << 1.0 / sigma, i / sigma;
  return J;
}

TEST(FitStatistics, AStraightLinesErrorsAreTheClosedFormOfItsNormalEquations) {
  const int n = 101;
  const double sigma = 0.3;
  Eigen::VectorXd estimate(2);
  estimate << 2.0, 0.5;
  const auto s = mh::cli::fit_statistics(estimate, estimate, line_jacobian(n, sigma), false);
  // var(b) = sigma^2 / sum (t - mean)^2, var(a) = sigma^2 sum t^2 / (n sum (t - mean)^2).
  double sxx = 0.0, st2 = 0.0;
  for (int i = 0; i < n; ++i) {
    sxx += (i - 50.0) * (i - 50.0);
    st2 += static_cast<double>(i) * i;
  }
  EXPECT_NEAR(s.parameters[1].std_error, sigma / std::sqrt(sxx), 1e-12);
  EXPECT_NEAR(s.parameters[0].std_error, sigma * std::sqrt(st2 / (n * sxx)), 1e-12);
  EXPECT_NEAR(s.parameters[1].ci_high - s.parameters[1].ci_low,
              2 * 1.959963984540054 * s.parameters[1].std_error, 1e-12);
  // corr(a, b) = -mean / sqrt(sum t^2 / n).
  EXPECT_NEAR(s.correlation(0, 1), -50.0 / std::sqrt(st2 / n), 1e-12);
  EXPECT_TRUE(s.parameters[0].identifiable && s.parameters[1].identifiable);
  // Weights estimated from the residuals: n / (n - k) more variance.
  const auto e = mh::cli::fit_statistics(estimate, estimate, line_jacobian(n, sigma), true);
  EXPECT_NEAR(e.parameters[1].std_error / s.parameters[1].std_error, std::sqrt(n / (n - 2.0)),
              1e-12);
}

TEST(FitStatistics, AParameterTheResidualsDoNotDependOnIsNotIdentifiable) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(50, 3);
  J.leftCols(2) = line_jacobian(50, 1.0);
  Eigen::VectorXd estimate(3);
  estimate << 2.0, 0.5, 7.0;
  const auto s = mh::cli::fit_statistics(estimate, estimate, J, false);
  EXPECT_TRUE(s.parameters[0].identifiable);
  EXPECT_TRUE(s.parameters[1].identifiable);
  EXPECT_FALSE(s.parameters[2].identifiable);
  EXPECT_NE(s.parameters[2].why.find("do not depend on it"), std::string::npos);
  EXPECT_TRUE(std::isnan(s.parameters[2].std_error));
  // The others' errors as if it were not there.
  const auto alone =
      mh::cli::fit_statistics(estimate.head(2), estimate.head(2), J.leftCols(2), false);
  EXPECT_DOUBLE_EQ(s.parameters[1].std_error, alone.parameters[1].std_error);
}

TEST(FitStatistics, TwoParametersThatActOnlyTogetherAreBothNotIdentifiable) {
  Eigen::MatrixXd J(40, 3);
  J.leftCols(2) = line_jacobian(40, 1.0);
  J.col(2) = J.col(1) * 2.0;  // p3 acts exactly as p2 does
  Eigen::VectorXd estimate(3);
  estimate << 1.0, 1.0, 1.0;
  const auto s = mh::cli::fit_statistics(estimate, estimate, J, false);
  EXPECT_TRUE(s.parameters[0].identifiable);
  EXPECT_FALSE(s.parameters[1].identifiable);
  EXPECT_FALSE(s.parameters[2].identifiable);
  EXPECT_NE(s.parameters[1].why.find("together"), std::string::npos);
}

TEST(FitStatistics, AParameterDeterminedOnlyToItsOwnSizeIsNotIdentifiable) {
  Eigen::MatrixXd J = line_jacobian(30, 1.0);
  J.col(1) *= 1e-3;  // a weak slope: its error is far above its value
  Eigen::VectorXd estimate(2);
  estimate << 1.0, 0.01;
  const auto s = mh::cli::fit_statistics(estimate, estimate, J, false);
  EXPECT_TRUE(s.parameters[0].identifiable);
  EXPECT_FALSE(s.parameters[1].identifiable);
  EXPECT_NE(s.parameters[1].why.find("only to +-"), std::string::npos);
}

// The same weak slope started at 0 (an initial angle, an offset): no size
// of its own to hold the error against, so its directions alone judge it,
// and its interval says how little the data know of it.
TEST(FitStatistics, AParameterStartedAtZeroIsJudgedByItsDirectionsAlone) {
  Eigen::MatrixXd J = line_jacobian(30, 1.0);
  J.col(1) *= 1e-3;
  Eigen::VectorXd estimate(2), initial(2);
  estimate << 1.0, 0.01;
  initial << 1.0, 0.0;
  const auto s = mh::cli::fit_statistics(initial, estimate, J, false);
  EXPECT_TRUE(s.parameters[1].identifiable);
  EXPECT_GT(s.parameters[1].std_error, 10.0 * estimate(1));
  EXPECT_LT(s.parameters[1].ci_low, 0.0);
  // Not a column of zeros, though: that stays not identifiable.
  J.col(1).setZero();
  EXPECT_FALSE(mh::cli::fit_statistics(initial, estimate, J, false).parameters[1].identifiable);
}

}  // namespace
