// A discrete extended Kalman filter on the run's own step: a model that
// tracks a running machine from its sensors (docs/estimation.md).
//
// The filter's state is the run's (state_vector.hpp): X_k, the accepted
// state of step k, with the covariance P of its error. Each step:
//  - update: the sensors with a sample at t_k (the others NaN) correct X_k
//    by the Kalman gain, y = h(X) + bias + noise with h the columns they
//    measure; the corrected state is put in the run (set_state_values:
//    made consistent, the constraints kept), and P by Joseph's form;
//  - predict: the run takes its step, X_{k+1} = f(X_k), and P goes through
//    the step's own map, P = Phi P Phi^T + Q h.
// Phi and the sensors' rows H = dh/dX are the linearisation of the step at
// X_k (linearization.hpp: the converged implicit step differenced, so
// double-step's dependent coordinates and penalty's projections included),
// taken once per step, before the update (the correction is small beside
// the step's nonlinearity). Q is the plant's noise: per state, the
// standard deviation its error gains over one second (a random walk; in
// the state's unit per sqrt(s)). The state's error is corrected into the
// run at every update and starts again from zero: the indirect
// (error-state) filter of Jaiswal et al. 2022 on the discrete step instead
// of its continuous Jacobian.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/linearization.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/core/state_vector.hpp"

namespace mh {

struct FilterSensor {
  std::string name;      // as the data name it
  std::string measures;  // a column `run` writes: z1, p2, a named state or output
  double noise = 0.0;    // its standard deviation, SI; above 0
  double bias = 0.0;     // a known offset of its readings
};

struct FilterNoise {
  Eigen::VectorXd plant;    // per state of X: unit/sqrt(s), 0 or more
  Eigen::VectorXd initial;  // per state of X: the initial error's standard deviation
};

class ExtendedKalmanFilter {
 public:
  // `sim` started, and outliving the filter. Throws std::invalid_argument
  // naming a sensor whose column the run does not write or whose noise is
  // not above 0, or a noise vector of another size than X or with a
  // negative or non-finite entry.
  ExtendedKalmanFilter(Simulation& sim, std::vector<FilterSensor> sensors,
                       const FilterNoise& noise);

  // The readings at the accepted time, one per sensor (NaN: no sample);
  // corrects the run's state with those present. Throws SimulationError
  // when the corrected state cannot be made consistent, or when the
  // filter diverges: the normalised innovations squared over the last
  // kDivergenceWindow updates average more than kDivergenceLimit times
  // their degrees of freedom (the filter no longer believes its model).
  void update(const Eigen::VectorXd& readings);
  // One step of the run, the covariance carried along.
  void predict();

  const std::vector<LinearVariable>& states() const { return states_; }
  const std::vector<FilterSensor>& sensors() const { return sensors_; }
  Eigen::VectorXd state() const { return state_values(sim_); }
  const Eigen::MatrixXd& covariance() const { return P_; }
  // Of the last update, per sensor (NaN for one without a sample): the
  // innovation y - h(X) and its standard deviation sqrt(S_ii).
  const Eigen::VectorXd& innovation() const { return innovation_; }
  const Eigen::VectorXd& innovation_sd() const { return innovation_sd_; }
  // nu^T S^-1 nu of the last update, and the samples it had (0: none).
  double nis() const { return nis_; }
  int samples() const { return samples_; }

  static constexpr int kDivergenceWindow = 200;
  static constexpr double kDivergenceLimit = 25.0;

 private:
  void linearize_here();
  Simulation& sim_;
  std::vector<FilterSensor> sensors_;
  std::vector<LinearVariable> states_;
  CsvLayout layout_;
  std::vector<std::size_t> columns_;   // per sensor: its column in layout_
  std::vector<std::string> measured_;  // per sensor: the column it measures
  std::vector<double> row_;            // one row of layout_
  Eigen::MatrixXd P_, Q_;
  Linearization lin_;
  long linearized_at_ = -1;  // the step lin_ is of
  Eigen::VectorXd innovation_, innovation_sd_;
  double nis_ = 0.0;
  int samples_ = 0;
  std::vector<double> window_;  // NIS / dof of the last updates, a ring
  long updates_ = 0;
};

}  // namespace mh
