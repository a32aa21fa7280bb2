// What every state estimator of a run shares (docs/estimation.md): the
// sensors it reads, the noise it is told, the state's covariance, the
// innovations of its last update and the watch for divergence. A filter is
// built on a started run and drives it: update() with the readings at the
// accepted time corrects the run's state (set_state_values), predict()
// steps it. ExtendedKalmanFilter (extended_kalman_filter.hpp) and
// UnscentedKalmanFilter (unscented_kalman_filter.hpp) are the two.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/held_parameters.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/core/state_vector.hpp"

namespace mh {

struct FilterSensor {
  std::string name;      // as the data name it
  std::string measures;  // a column `run` writes: z1, p2, a named state or output
  double noise = 0.0;    // its standard deviation, SI; above 0
  double bias = 0.0;     // a known offset of its readings
  // s: its reading given at t is of the state at t - delay (a transducer's
  // or a network's latency); a whole number of the run's steps.
  double delay = 0.0;
};

// The filter's noise, per state of X (state_vector.hpp), then per
// parameter it estimates beside them.
struct FilterNoise {
  // The standard deviation the state's error gains over one second (a
  // random walk; the state's unit per sqrt(s)): Q h per step.
  Eigen::VectorXd plant;
  Eigen::VectorXd initial;  // the initial error's standard deviation
  // The same of each parameter (in its path's units): how fast it may
  // drift, and how far from its model value it may start.
  Eigen::VectorXd parameter_plant, parameter_initial;
};

class StateFilter {
 public:
  virtual ~StateFilter() = default;
  StateFilter(const StateFilter&) = delete;
  StateFilter& operator=(const StateFilter&) = delete;

  // The readings at the accepted time, one per sensor (NaN: no sample):
  // corrects the run's state with those present. Throws
  // std::invalid_argument for a reading count other than the sensors' or
  // an infinite reading; SimulationError when the correction cannot be
  // put into the run, or when the filter diverges: the normalised
  // innovations squared over the last kDivergenceWindow updates average
  // more than kDivergenceLimit times their degrees of freedom. Either
  // names the sensor furthest off.
  // A delayed sensor's reading is of the state `delay` before: the filter
  // goes back to that step (it keeps its last steps' states, covariances
  // and readings), corrects it there with every reading of that step, and
  // steps forward again to now with each later step's readings (Larsen et
  // al.'s "rollback and replay", exact for the filter's own model); a
  // reading of a step before the filter's start is dropped.
  void update(const Eigen::VectorXd& readings);
  // One step of the run, the covariance carried along.
  void predict();

  // The filter's state: X's entries, then the parameters it estimates
  // (named by their paths, unit empty).
  const std::vector<LinearVariable>& states() const { return states_; }
  const std::vector<FilterSensor>& sensors() const { return sensors_; }
  Eigen::Index num_x() const { return num_x_; }  // X's entries; the parameters follow
  Eigen::Index num_parameters() const { return held_.size(); }
  Eigen::VectorXd state() const;
  const Eigen::MatrixXd& covariance() const { return P_; }
  // Of the last update, per sensor (NaN for one without a sample): the
  // innovation y - h(X) - bias and its standard deviation.
  const Eigen::VectorXd& innovation() const { return innovation_; }
  const Eigen::VectorXd& innovation_sd() const { return innovation_sd_; }
  // nu^T S^-1 nu of the last update, and the samples it had (0: none).
  double nis() const { return nis_; }
  int samples() const { return samples_; }

  static constexpr int kDivergenceWindow = 200;
  static constexpr double kDivergenceLimit = 25.0;

 protected:
  // `sim` started, and outliving the filter. Throws std::invalid_argument
  // naming a sensor whose column the run does not write or whose noise is
  // not above 0, or a noise vector of another size than X or with a
  // negative or non-finite entry.
  // `parameters`: estimated beside the state (augmented states), held in
  // place (held_parameters.hpp) and corrected with it; HeldParameters'
  // refusals.
  StateFilter(Simulation& sim, std::vector<FilterSensor> sensors, const FilterNoise& noise,
              std::vector<ParameterDirection> parameters);

  // The filter's own update and prediction, at the run's step.
  virtual void update_now(const Eigen::VectorXd& readings) = 0;
  virtual void predict_now() = 0;
  // The run was put back to an earlier step: what the filter keeps of a
  // step (a linearisation) is no longer of the run's state.
  virtual void rolled_back() {}

  // The readings' checks; the sensors with a sample (and samples_), the
  // last update's innovations cleared.
  std::vector<Eigen::Index> take(const Eigen::VectorXd& readings);
  // What sensor i reads of the run's state now: h_i(X) + bias.
  double model_reading(Eigen::Index i);
  // The innovations nu of the sensors `used` and their covariance S:
  // recorded, and the divergence watched (throws).
  void record(const std::vector<Eigen::Index>& used, const Eigen::VectorXd& nu,
              const Eigen::MatrixXd& S);
  // The corrected state into the run (throws naming the sensor furthest off).
  void correct(const Eigen::VectorXd& x);
  // An augmented state into the run: its parameters at their values, then
  // X (set_state_values); throws as they do.
  void put(const Eigen::VectorXd& x);

  Simulation& sim_;
  std::vector<FilterSensor> sensors_;
  std::vector<LinearVariable> states_;
  std::vector<std::string> measured_;  // per sensor: the column it measures
  Eigen::MatrixXd P_, Q_;
  HeldParameters held_;

 private:
  Eigen::Index num_x_ = 0;
  std::string furthest() const;
  CsvLayout layout_;
  std::vector<std::size_t> columns_;  // per sensor: its column in layout_
  std::vector<double> row_;           // one row of layout_
  Eigen::VectorXd innovation_, innovation_sd_;
  double nis_ = 0.0;
  int samples_ = 0;
  std::vector<double> window_;  // NIS / dof of the last updates, a ring
  long updates_ = 0;

  // Delayed sensors: each one's delay in steps; the filter as it was at
  // each of the last max_delay_ + 1 steps before its update there, and
  // every reading of that step so far (a ring by step).
  struct Past {
    long step = -1;
    RunState run;
    Eigen::MatrixXd P;
    Eigen::VectorXd offsets, readings;
    std::vector<double> window;
    long updates = 0;
  };
  std::vector<long> delay_steps_;
  long max_delay_ = 0;
  std::vector<Past> past_;
  Past& past(long step) { return past_[static_cast<size_t>(step) % past_.size()]; }
  // This step's entry: the filter now, no reading yet (`keep`: its readings kept).
  void remember(bool keep);
};

}  // namespace mh
