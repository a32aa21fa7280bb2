// An unscented Kalman filter on the run (docs/estimation.md): the
// extended filter's comparison, with no derivative of the step. The
// unscented transform of Julier and Uhlmann with kappa = 0: 2n sigma points
// X +- sqrt(n) s_i, s_i the columns of a square root of P, each of weight
// 1/(2n). Each point is put into the run (set_state_values: made
// consistent, the constraints kept) from the same saved state and
//  - predict: stepped; their mean is the prediction (put into the run after
//    its own step) and their spread plus Q h its covariance;
//  - update: read by the sensors; the gain K = P_xy P_yy^-1 of their
//    spreads corrects the state, P - K P_yy K^T its covariance.
// n + 1 times the extended filter's state settings, and 2n steps a step.
#pragma once

#include <vector>

#include "monohydra/core/state_filter.hpp"

namespace mh {

class UnscentedKalmanFilter : public StateFilter {
 public:
  UnscentedKalmanFilter(Simulation& sim, std::vector<FilterSensor> sensors,
                        const FilterNoise& noise, std::vector<ParameterDirection> parameters = {})
      : StateFilter(sim, std::move(sensors), noise, std::move(parameters)) {}

 private:
  void update_now(const Eigen::VectorXd& readings) override;
  void predict_now() override;
  // sqrt(n) times a square root of P: its columns spread the sigma points.
  Eigen::MatrixXd spread() const;
};

}  // namespace mh
