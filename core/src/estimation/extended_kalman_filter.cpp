// The discrete extended Kalman filter on the run's step
// (extended_kalman_filter.hpp, docs/estimation.md).
#include "monohydra/core/extended_kalman_filter.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "monohydra/core/run_state.hpp"

namespace mh {

// The step's map and the sensors' rows at the accepted state, once per step.
void ExtendedKalmanFilter::linearize_here() {
  if (linearized_at_ == sim_.step_index()) return;
  lin_ = linearize(sim_, measured_, {false, false});  // the map and C alone, one-sided
  linearized_at_ = sim_.step_index();
}

double ExtendedKalmanFilter::parameter_step(Eigen::Index j) const {
  const double v = held_.parameters()[static_cast<size_t>(j)].value + held_.offsets()[j];
  return 1e-6 * (v != 0.0 ? std::abs(v) : 1.0);
}

template <class Prepare, class Measure>
void ExtendedKalmanFilter::parameter_columns(const Prepare& prepare, const Measure& measure,
                                             Eigen::Ref<Eigen::MatrixXd> out) {
  const RunState saved = sim_.save_state();
  const Eigen::VectorXd offsets = held_.offsets();
  Eigen::VectorXd plus(out.rows()), minus(out.rows());
  for (Eigen::Index j = 0; j < out.cols(); ++j) {
    const double d = parameter_step(j);
    for (const double sign : {1.0, -1.0}) {
      Eigen::VectorXd moved = offsets;
      moved[j] += sign * d;
      held_.set(moved);
      prepare(saved);
      measure(sign > 0.0 ? plus : minus);
    }
    held_.set(offsets);
    sim_.restore_state(saved);
    out.col(j) = (plus - minus) / (2.0 * d);
  }
}

void ExtendedKalmanFilter::update_now(const Eigen::VectorXd& readings) {
  const std::vector<Eigen::Index> used = take(readings);
  if (used.empty()) return;
  linearize_here();
  const auto q = static_cast<Eigen::Index>(used.size());
  const auto n = P_.rows();
  const Eigen::Index nx = num_x(), k_p = num_parameters();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(q, n);
  Eigen::VectorXd nu(q);
  Eigen::VectorXd r(q);
  Eigen::VectorXd now(q);
  for (Eigen::Index k = 0; k < q; ++k) now[k] = model_reading(used[static_cast<size_t>(k)]);
  if (k_p > 0) {
    // The readings at the same X with each parameter moved: the run made
    // consistent there.
    const Eigen::VectorXd x = state_values(sim_);
    parameter_columns([&](const RunState&) { set_state_values(sim_, x); },
                      [&](Eigen::VectorXd& v) {
                        for (Eigen::Index k = 0; k < q; ++k)
                          v[k] = model_reading(used[static_cast<size_t>(k)]);
                      },
                      H.rightCols(k_p));
  }
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    H.row(k).head(nx) = lin_.C.row(i);
    nu[k] = readings[i] - now[k];
    const double sd = sensors_[static_cast<size_t>(i)].noise;
    r[k] = sd * sd;
  }
  const Eigen::MatrixXd PHt = P_ * H.transpose();
  Eigen::MatrixXd S = H * PHt;
  S.diagonal() += r;
  record(used, nu, S);
  const Eigen::MatrixXd K = S.ldlt().solve(PHt.transpose()).transpose();  // P H^T S^-1
  correct(state() + K * nu);
  // Joseph's form: symmetric and positive whatever the gain's round-off.
  Eigen::MatrixXd IKH = -K * H;
  IKH.diagonal().array() += 1.0;
  P_ = IKH * P_ * IKH.transpose() + K * r.asDiagonal() * K.transpose();
}

void ExtendedKalmanFilter::predict_now() {
  linearize_here();
  const Eigen::Index nx = num_x(), k_p = num_parameters();
  Eigen::MatrixXd F = Eigen::MatrixXd::Identity(nx + k_p, nx + k_p);
  F.topLeftCorner(nx, nx) = lin_.Phi;
  if (k_p > 0) {
    // d X_{k+1} / d p: the step from the same saved state, p moved.
    parameter_columns(
        [&](const RunState& saved) {
          sim_.restore_state(saved);
          sim_.step();
        },
        [&](Eigen::VectorXd& v) { v = state_values(sim_); }, F.topRightCorner(nx, k_p));
  }
  sim_.step();
  P_ = F * P_ * F.transpose() + Q_;
  P_ = 0.5 * (P_ + P_.transpose());
}

}  // namespace mh
