// The unscented Kalman filter on the run (unscented_kalman_filter.hpp,
// docs/estimation.md).
#include "monohydra/core/unscented_kalman_filter.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "monohydra/core/run_state.hpp"

namespace mh {

// P's entries span twenty decades (rad^2 beside Pa^2): its square root is
// taken of the correlations, P = D C D with D the standard deviations, as
// D sqrt(C); a state without variance spreads no point.
Eigen::MatrixXd UnscentedKalmanFilter::spread() const {
  const Eigen::Index n = P_.rows();
  Eigen::VectorXd d = P_.diagonal().cwiseMax(0.0).cwiseSqrt();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (d[i] > 0.0) inverse[i] = 1.0 / d[i];
  const Eigen::MatrixXd c = inverse.asDiagonal() * P_ * inverse.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(c);
  const Eigen::MatrixXd root = eigen.eigenvectors() *
                               eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
                               eigen.eigenvectors().transpose();
  return std::sqrt(static_cast<double>(n)) * (d.asDiagonal() * root);
}

void UnscentedKalmanFilter::predict_now() {
  const Eigen::Index n = P_.rows();
  const RunState saved = sim_.save_state();
  const Eigen::VectorXd offsets = held_.offsets();
  const Eigen::VectorXd x = state();
  const Eigen::MatrixXd s = spread();
  Eigen::MatrixXd points(n, 2 * n);
  for (Eigen::Index j = 0; j < 2 * n; ++j) {
    sim_.restore_state(saved);
    put(j < n ? Eigen::VectorXd(x + s.col(j)) : Eigen::VectorXd(x - s.col(j - n)));
    sim_.step();
    points.col(j) = state();
  }
  held_.set(offsets);
  sim_.restore_state(saved);
  sim_.step();
  const Eigen::VectorXd mean = points.rowwise().mean();
  const Eigen::MatrixXd apart = points.colwise() - mean;
  P_ = apart * apart.transpose() / static_cast<double>(2 * n) + Q_;
  P_ = 0.5 * (P_ + P_.transpose());
  put(mean);
}

void UnscentedKalmanFilter::update_now(const Eigen::VectorXd& readings) {
  const std::vector<Eigen::Index> used = take(readings);
  if (used.empty()) return;
  const Eigen::Index n = P_.rows();
  const auto q = static_cast<Eigen::Index>(used.size());
  const RunState saved = sim_.save_state();
  const Eigen::VectorXd offsets = held_.offsets();
  const Eigen::VectorXd x = state();
  const Eigen::MatrixXd s = spread();
  Eigen::MatrixXd points(n, 2 * n), read(q, 2 * n);
  for (Eigen::Index j = 0; j < 2 * n; ++j) {
    sim_.restore_state(saved);
    put(j < n ? Eigen::VectorXd(x + s.col(j)) : Eigen::VectorXd(x - s.col(j - n)));
    points.col(j) = state();
    for (Eigen::Index k = 0; k < q; ++k) read(k, j) = model_reading(used[static_cast<size_t>(k)]);
  }
  held_.set(offsets);
  sim_.restore_state(saved);
  const Eigen::VectorXd y_mean = read.rowwise().mean();
  const Eigen::MatrixXd y_apart = read.colwise() - y_mean;
  const Eigen::MatrixXd x_apart = points.colwise() - x;
  const auto w = 1.0 / static_cast<double>(2 * n);
  Eigen::MatrixXd Pyy = w * y_apart * y_apart.transpose();
  Eigen::VectorXd nu(q);
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    const double sd = sensors_[static_cast<size_t>(i)].noise;
    Pyy(k, k) += sd * sd;
    nu[k] = readings[i] - y_mean[k];
  }
  record(used, nu, Pyy);
  const Eigen::MatrixXd Pxy = w * x_apart * y_apart.transpose();
  const Eigen::MatrixXd K = Pyy.ldlt().solve(Pxy.transpose()).transpose();
  correct(x + K * nu);
  P_ -= K * Pyy * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
}

}  // namespace mh
