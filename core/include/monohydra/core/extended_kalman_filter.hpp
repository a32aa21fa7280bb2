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
// the step's nonlinearity). The state's error is corrected into the run at
// every update and starts again from zero: the indirect (error-state)
// filter of Jaiswal et al. 2022 on the discrete step instead of its
// continuous Jacobian.
// Parameters estimated beside the state (Khadim et al. 2021's augmented
// filter) are constant in the model, a random walk in the filter: their
// columns of the step's map, d X_{k+1} / d p, are central differences of the
// step from the same saved state with p moved in place, and their columns
// of H the sensors' readings at the same X with p moved (an output such as
// a force depends on p directly).
#pragma once

#include <vector>

#include "monohydra/core/linearization.hpp"
#include "monohydra/core/state_filter.hpp"

namespace mh {

class ExtendedKalmanFilter : public StateFilter {
 public:
  ExtendedKalmanFilter(Simulation& sim, std::vector<FilterSensor> sensors, const FilterNoise& noise,
                       std::vector<ParameterDirection> parameters = {})
      : StateFilter(sim, std::move(sensors), noise, std::move(parameters)) {}

 private:
  void update_now(const Eigen::VectorXd& readings) override;
  void predict_now() override;
  void rolled_back() override { linearized_at_ = -1; }
  void linearize_here();
  // Parameter j's difference step: a millionth of its value (of 1 at 0).
  double parameter_step(Eigen::Index j) const;
  // Column j of `out`: the central difference over parameter j of what
  // `measure` reads once `prepare(saved)` has brought the run there with
  // that parameter moved; the offsets and the run's saved state put back
  // after each parameter.
  template <class Prepare, class Measure>
  void parameter_columns(const Prepare& prepare, const Measure& measure,
                         Eigen::Ref<Eigen::MatrixXd> out);
  Linearization lin_;
  long linearized_at_ = -1;  // the step lin_ is of
};

}  // namespace mh
