// The discrete extended Kalman filter on the run's step
// (extended_kalman_filter.hpp, docs/estimation.md).
#include "monohydra/core/extended_kalman_filter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "monohydra/cpp/number_text.hpp"

namespace mh {

using monohydra::short_number;

namespace {

void check_noise(const Eigen::VectorXd& v, const std::vector<LinearVariable>& states,
                 const char* what) {
  if (v.size() != static_cast<Eigen::Index>(states.size()))
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(v.size()) +
                                " values for a state of " + std::to_string(states.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!(v[i] >= 0.0) || !std::isfinite(v[i]))
      throw std::invalid_argument(std::string(what) + " of " + states[static_cast<size_t>(i)].name +
                                  ": expected a standard deviation of 0 or more");
}

}  // namespace

ExtendedKalmanFilter::ExtendedKalmanFilter(Simulation& sim, std::vector<FilterSensor> sensors,
                                           const FilterNoise& noise)
    : sim_(sim),
      sensors_(std::move(sensors)),
      states_(state_variables(sim)),
      layout_(sim),
      row_(layout_.names().size()) {
  if (sensors_.empty()) throw std::invalid_argument("a filter needs at least one sensor");
  for (const FilterSensor& s : sensors_) {
    if (!(s.noise > 0.0) || !std::isfinite(s.noise))
      throw std::invalid_argument("sensor '" + s.name +
                                  "': expected a noise (standard deviation) above 0");
    const auto& names = layout_.names();
    const auto it = std::find(names.begin(), names.end(), s.measures);
    if (it == names.end() || it == names.begin())
      throw std::invalid_argument("sensor '" + s.name + "' measures '" + s.measures +
                                  "', which is not a column this run writes");
    columns_.push_back(static_cast<std::size_t>(it - names.begin()));
    measured_.push_back(s.measures);
  }
  check_noise(noise.plant, states_, "plant noise");
  check_noise(noise.initial, states_, "initial standard deviation");
  const double h = sim.settings().dt;
  Q_ = noise.plant.array().square().matrix().asDiagonal();
  Q_ *= h;
  P_ = noise.initial.array().square().matrix().asDiagonal();
  const auto m = static_cast<Eigen::Index>(sensors_.size());
  innovation_ = Eigen::VectorXd::Constant(m, NAN);
  innovation_sd_ = Eigen::VectorXd::Constant(m, NAN);
  window_.assign(kDivergenceWindow, 0.0);
}

// The step's map and the sensors' rows at the accepted state, once per step.
void ExtendedKalmanFilter::linearize_here() {
  if (linearized_at_ == sim_.step_index()) return;
  lin_ = linearize(sim_, measured_);
  linearized_at_ = sim_.step_index();
}

void ExtendedKalmanFilter::update(const Eigen::VectorXd& readings) {
  const auto m = static_cast<Eigen::Index>(sensors_.size());
  if (readings.size() != m)
    throw std::invalid_argument("update: " + std::to_string(readings.size()) + " readings for " +
                                std::to_string(m) + " sensors");
  innovation_.setConstant(NAN);
  innovation_sd_.setConstant(NAN);
  nis_ = NAN;
  std::vector<Eigen::Index> used;
  for (Eigen::Index i = 0; i < m; ++i)
    if (!std::isnan(readings[i])) {
      if (!std::isfinite(readings[i]))
        throw std::invalid_argument("update: sensor '" + sensors_[static_cast<size_t>(i)].name +
                                    "' read " + std::to_string(readings[i]));
      used.push_back(i);
    }
  samples_ = static_cast<int>(used.size());
  if (used.empty()) return;
  linearize_here();
  layout_.values(sim_, row_.data());
  const auto q = static_cast<Eigen::Index>(used.size());
  const auto n = P_.rows();
  Eigen::MatrixXd H(q, n);
  Eigen::VectorXd nu(q);
  Eigen::VectorXd r(q);
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    const FilterSensor& s = sensors_[static_cast<size_t>(i)];
    H.row(k) = lin_.C.row(i);
    nu[k] = readings[i] - (row_[columns_[static_cast<size_t>(i)]] + s.bias);
    r[k] = s.noise * s.noise;
  }
  const Eigen::MatrixXd PHt = P_ * H.transpose();
  Eigen::MatrixXd S = H * PHt;
  S.diagonal() += r;
  const Eigen::LDLT<Eigen::MatrixXd> S_ldlt(S);
  const Eigen::MatrixXd K = S_ldlt.solve(PHt.transpose()).transpose();  // P H^T S^-1
  nis_ = nu.dot(S_ldlt.solve(nu));
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    innovation_[i] = nu[k];
    innovation_sd_[i] = std::sqrt(S(k, k));
  }
  // The sensor furthest off, in its innovation's standard deviations: what
  // a refusal names.
  const auto furthest = [&] {
    std::string worst;
    double largest = -1.0;
    for (Eigen::Index i = 0; i < m; ++i)
      if (!std::isnan(innovation_[i]) && std::abs(innovation_[i] / innovation_sd_[i]) > largest) {
        largest = std::abs(innovation_[i] / innovation_sd_[i]);
        worst = sensors_[static_cast<size_t>(i)].name;
      }
    return "sensor '" + worst + "' is now " + short_number(largest) + " standard deviations off";
  };
  // Divergence: the innovations' normalised squares, per degree of freedom,
  // averaged over a window.
  window_[static_cast<size_t>(updates_ % kDivergenceWindow)] = nis_ / static_cast<double>(q);
  ++updates_;
  if (updates_ >= kDivergenceWindow) {
    const double mean =
        std::accumulate(window_.begin(), window_.end(), 0.0) / static_cast<double>(window_.size());
    if (!(mean <= kDivergenceLimit))
      throw SimulationError(sim_.time(), sim_.step_index(),
                            "the filter diverges: its innovations have averaged " +
                                short_number(mean) + " times their expected size squared over " +
                                std::to_string(kDivergenceWindow) + " updates (" + furthest() +
                                "): the model or its noise levels do not describe the data");
  }
  try {
    set_state_values(sim_, state_values(sim_) + K * nu);
  } catch (const SimulationError& err) {
    throw SimulationError(sim_.time(), sim_.step_index(),
                          "the filter's correction cannot be applied (" + err.reason() + "; " +
                              furthest() +
                              "): the model or its noise levels do not describe the data");
  }
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
