// What the run's state estimators share (state_filter.hpp).
#include "monohydra/core/state_filter.hpp"

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

// A reading per sensor, or why not.
void check_count(const Eigen::VectorXd& readings, size_t sensors) {
  const auto m = static_cast<Eigen::Index>(sensors);
  if (readings.size() != m)
    throw std::invalid_argument("update: " + std::to_string(readings.size()) + " readings for " +
                                std::to_string(m) + " sensors");
}

}  // namespace

StateFilter::StateFilter(Simulation& sim, std::vector<FilterSensor> sensors,
                         const FilterNoise& noise, std::vector<ParameterDirection> parameters)
    : sim_(sim),
      sensors_(std::move(sensors)),
      states_(state_variables(sim)),
      held_(sim, std::move(parameters)),
      layout_(sim),
      row_(layout_.names().size()) {
  num_x_ = static_cast<Eigen::Index>(states_.size());
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
  std::vector<LinearVariable> params;
  for (const ParameterDirection& p : held_.parameters()) params.push_back({p.path, ""});
  const Eigen::Index k = held_.size();
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(0);
  const Eigen::VectorXd& p_plant = k > 0 ? noise.parameter_plant : none;
  const Eigen::VectorXd& p_initial = k > 0 ? noise.parameter_initial : none;
  check_noise(p_plant, params, "parameter noise");
  check_noise(p_initial, params, "parameter initial standard deviation");
  states_.insert(states_.end(), params.begin(), params.end());
  Eigen::VectorXd plant(num_x_ + k), initial(num_x_ + k);
  plant << noise.plant, p_plant;
  initial << noise.initial, p_initial;
  Q_ = plant.array().square().matrix().asDiagonal();
  Q_ *= sim.settings().dt;
  P_ = initial.array().square().matrix().asDiagonal();
  const auto m = static_cast<Eigen::Index>(sensors_.size());
  innovation_ = Eigen::VectorXd::Constant(m, NAN);
  innovation_sd_ = Eigen::VectorXd::Constant(m, NAN);
  window_.assign(kDivergenceWindow, 0.0);
  const double dt = sim.settings().dt;
  for (const FilterSensor& s : sensors_) {
    const long d = std::lround(s.delay / dt);
    if (!(s.delay >= 0.0) || std::abs(static_cast<double>(d) * dt - s.delay) > 1e-9 * dt)
      throw std::invalid_argument("sensor '" + s.name + "': a delay of " + short_number(s.delay) +
                                  " s: expected a whole number of the run's steps of " +
                                  short_number(dt) + " s, 0 or more");
    delay_steps_.push_back(d);
    max_delay_ = std::max(max_delay_, d);
  }
  if (max_delay_ > 0) {
    past_.resize(static_cast<size_t>(max_delay_ + 1));
    remember(false);
  }
}

void StateFilter::remember(bool keep) {
  Past& p = past(sim_.step_index());
  p.step = sim_.step_index();
  sim_.save_state(p.run);
  p.P = P_;
  p.offsets = held_.offsets();
  p.window = window_;
  p.updates = updates_;
  if (!keep)
    p.readings = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(sensors_.size()), NAN);
}

void StateFilter::predict() {
  predict_now();
  if (max_delay_ > 0) remember(false);
}

void StateFilter::update(const Eigen::VectorXd& readings) {
  if (max_delay_ == 0) {
    update_now(readings);
    return;
  }
  check_count(readings, sensors_.size());
  const auto m = static_cast<Eigen::Index>(sensors_.size());
  // Each reading to the step it is of; the earliest such step.
  const long k = sim_.step_index();
  Eigen::VectorXd now = Eigen::VectorXd::Constant(m, NAN);
  long from = k;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (std::isnan(readings[i])) continue;
    if (std::isinf(readings[i])) {
      update_now(readings);  // its refusal
      return;
    }
    const long j = k - delay_steps_[static_cast<size_t>(i)];
    if (j == k) now[i] = readings[i];
    if (j < 0 || past(j).step != j) continue;  // before the filter's start
    past(j).readings[i] = readings[i];
    from = std::min(from, j);
  }
  if (from == k) {
    update_now(now);
    return;
  }
  // Back to the earliest, each step's readings again, forward to now.
  const Past& back = past(from);
  held_.set(back.offsets);
  sim_.restore_state(back.run);
  P_ = back.P;
  window_ = back.window;
  updates_ = back.updates;
  rolled_back();
  for (long j = from;; ++j) {
    update_now(past(j).readings);
    if (j == k) break;
    predict_now();
    remember(true);
  }
}

std::vector<Eigen::Index> StateFilter::take(const Eigen::VectorXd& readings) {
  check_count(readings, sensors_.size());
  const auto m = static_cast<Eigen::Index>(sensors_.size());
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
  return used;
}

double StateFilter::model_reading(Eigen::Index i) {
  layout_.values(sim_, row_.data());
  return row_[columns_[static_cast<size_t>(i)]] + sensors_[static_cast<size_t>(i)].bias;
}

std::string StateFilter::furthest() const {
  std::string worst;
  double largest = -1.0;
  for (Eigen::Index i = 0; i < innovation_.size(); ++i)
    if (!std::isnan(innovation_[i]) && std::abs(innovation_[i] / innovation_sd_[i]) > largest) {
      largest = std::abs(innovation_[i] / innovation_sd_[i]);
      worst = sensors_[static_cast<size_t>(i)].name;
    }
  return "sensor '" + worst + "' is now " + short_number(largest) + " standard deviations off";
}

void StateFilter::record(const std::vector<Eigen::Index>& used, const Eigen::VectorXd& nu,
                         const Eigen::MatrixXd& S) {
  const auto q = static_cast<Eigen::Index>(used.size());
  nis_ = nu.dot(S.ldlt().solve(nu));
  for (Eigen::Index k = 0; k < q; ++k) {
    const Eigen::Index i = used[static_cast<size_t>(k)];
    innovation_[i] = nu[k];
    innovation_sd_[i] = std::sqrt(S(k, k));
  }
  // Divergence: the normalised innovations squared, per degree of freedom,
  // averaged over a window.
  window_[static_cast<size_t>(updates_ % kDivergenceWindow)] = nis_ / static_cast<double>(q);
  ++updates_;
  if (updates_ < kDivergenceWindow) return;
  const double mean =
      std::accumulate(window_.begin(), window_.end(), 0.0) / static_cast<double>(window_.size());
  if (!(mean <= kDivergenceLimit))
    throw SimulationError(sim_.time(), sim_.step_index(),
                          "the filter diverges: its innovations have averaged " +
                              short_number(mean) + " times their expected size squared over " +
                              std::to_string(kDivergenceWindow) + " updates (" + furthest() +
                              "): the model or its noise levels do not describe the data");
}

Eigen::VectorXd StateFilter::state() const {
  Eigen::VectorXd x(num_x_ + held_.size());
  x << state_values(sim_), held_.values();
  return x;
}

void StateFilter::put(const Eigen::VectorXd& x) {
  if (held_.size() > 0) {
    Eigen::VectorXd offsets = x.tail(held_.size());
    for (Eigen::Index j = 0; j < held_.size(); ++j)
      offsets[j] -= held_.parameters()[static_cast<size_t>(j)].value;
    held_.set(offsets);
  }
  set_state_values(sim_, x.head(num_x_));
}

void StateFilter::correct(const Eigen::VectorXd& x) {
  try {
    put(x);
  } catch (const std::invalid_argument& err) {
    throw SimulationError(sim_.time(), sim_.step_index(),
                          "the filter's correction cannot be applied (" + std::string(err.what()) +
                              "; " + furthest() +
                              "): the model or its noise levels do not describe the data");
  } catch (const SimulationError& err) {
    throw SimulationError(sim_.time(), sim_.step_index(),
                          "the filter's correction cannot be applied (" + err.reason() + "; " +
                              furthest() +
                              "): the model or its noise levels do not describe the data");
  }
}

}  // namespace mh
