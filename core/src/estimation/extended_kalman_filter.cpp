// The discrete extended Kalman filter on the run's step
// (extended_kalman_filter.hpp, docs/estimation.md).
#include "monohydra/core/extended_kalman_filter.hpp"

#include <Eigen/Cholesky>

namespace mh {

// The step's map and the sensors' rows at the accepted state, once per step.
void ExtendedKalmanFilter::linearize_here() {
  if (linearized_at_ == sim_.step_index()) return;
  lin_ = linearize(sim_, measured_);
  linearized_at_ = sim_.step_index();
}

void ExtendedKalmanFilter::update(const Eigen::VectorXd& readings) {
  const std::vector<Eigen::Index> used = take(readings);
  if (used.empty()) return;
  linearize_here();
  const auto q = static_cast<Eigen::Index>(used.size());
  const auto n = P_.rows();
  Eigen::MatrixXd H(q, n);
  Eigen::VectorXd nu(q);
  Eigen::VectorXd r(q);
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    H.row(k) = lin_.C.row(i);
    nu[k] = readings[i] - model_reading(i);
    const double sd = sensors_[static_cast<size_t>(i)].noise;
    r[k] = sd * sd;
  }
  const Eigen::MatrixXd PHt = P_ * H.transpose();
  Eigen::MatrixXd S = H * PHt;
  S.diagonal() += r;
  record(used, nu, S);
  const Eigen::MatrixXd K = S.ldlt().solve(PHt.transpose()).transpose();  // P H^T S^-1
  correct(state_values(sim_) + K * nu);
  // Joseph's form: symmetric and positive whatever the gain's round-off.
  Eigen::MatrixXd IKH = -K * H;
  IKH.diagonal().array() += 1.0;
  P_ = IKH * P_ * IKH.transpose() + K * r.asDiagonal() * K.transpose();
}

void ExtendedKalmanFilter::predict() {
  linearize_here();
  sim_.step();
  P_ = lin_.Phi * P_ * lin_.Phi.transpose() + Q_;
  P_ = 0.5 * (P_ + P_.transpose());
}

}  // namespace mh
