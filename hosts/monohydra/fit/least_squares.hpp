// The fit itself: nonlinear least squares of the model's predictions against
// the measured samples, weighted by each column's noise level, solved by
// Ceres (Levenberg-Marquardt, dense QR: k is small, the samples many) on the
// exact Jacobian the forward sensitivities give, within the parameters'
// bounds. A column without a noise level is weighted by its own residual
// RMS at the solution: the fit is solved again with the new weights until
// they hold to 1 %, so that columns in different units count alike.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "sampled_run.hpp"

namespace mh::cli {

struct FitResult {
  bool solved = false;
  std::string why;  // when not: the reason
  Eigen::VectorXd estimate;
  Eigen::VectorXd predicted, predicted_initial;  // per sample
  Eigen::MatrixXd jacobian;                      // weighted: d r / d p at the estimate
  std::vector<double> sigma;                     // per measured column, the weights used
  bool sigmas_estimated = false;                 // some come from the residuals
  int iterations = 0;                            // Levenberg-Marquardt's, all rounds
  int rounds = 0;                                // of weights
  double initial_cost = 0.0, final_cost = 0.0;   // 1/2 sum r^2 with the last weights
};

// Each measured column's RMS of (predicted - measured), `predicted` one value
// per sample of `run`.
std::vector<double> residual_rms(const SampledRun& run, const Eigen::VectorXd& predicted);

// `noise`: per measured column, its standard deviation (0: estimate it).
// Within run.lower() and run.upper().
FitResult fit_parameters(const SampledRun& run, const std::vector<double>& noise,
                         int max_iterations);

}  // namespace mh::cli
