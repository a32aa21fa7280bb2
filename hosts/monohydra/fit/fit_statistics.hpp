// What the data say of each estimate (docs/identification.md): from the
// weighted residuals r = (model - measured) / sigma and their Jacobian J at
// the solution, the covariance (J^T J)^-1 (times N / (N - k) when the sigmas
// were estimated from the residuals themselves), standard errors, 95 %
// intervals (normal: N >> k), the correlations, and which parameters the
// data cannot determine.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace mh::cli {

struct ParameterStatistics {
  bool identifiable = true;
  std::string why;  // when not: what the data leave open
  double std_error = 0.0, ci_low = 0.0, ci_high = 0.0;
};

struct FitStatistics {
  std::vector<ParameterStatistics> parameters;
  Eigen::MatrixXd correlation;  // k x k; NaN in rows and columns of unidentifiable ones
};

// The largest relative standard error an identifiable parameter may have:
// beyond it the 95 % interval spans the value's own size, and the number
// says nothing the data determined.
inline constexpr double kLargestRelativeError = 0.5;
// Singular values of the Jacobian (columns scaled by each parameter's size)
// below this fraction of the largest are directions the data do not see.
inline constexpr double kSingularRatio = 1e-7;

// `initial` the parameters the fit started from (one started at 0 is not
// held to kLargestRelativeError), `estimate` the parameters at the
// solution, `J` (N x k) the weighted residuals' d r / d p there;
// `sigmas_estimated`: the weights are the residuals' own RMS (the
// covariance takes N / (N - k)).
FitStatistics fit_statistics(const Eigen::VectorXd& initial, const Eigen::VectorXd& estimate,
                             const Eigen::MatrixXd& J, bool sigmas_estimated);

}  // namespace mh::cli
