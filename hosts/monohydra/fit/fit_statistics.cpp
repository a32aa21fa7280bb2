#include "fit_statistics.hpp"

#include <cmath>
#include <limits>

namespace mh::cli {

namespace {

constexpr double kNormal975 = 1.959963984540054;  // the standard normal's 97.5 % quantile

double size_of(double v) {
  return v != 0.0 ? std::abs(v) : 1.0;
}

}  // namespace

FitStatistics fit_statistics(const Eigen::VectorXd& initial, const Eigen::VectorXd& estimate,
                             const Eigen::MatrixXd& J, bool sigmas_estimated) {
  const Eigen::Index k = estimate.size(), n = J.rows();
  FitStatistics out;
  out.parameters.assign(static_cast<size_t>(k), {});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.correlation = Eigen::MatrixXd::Constant(k, k, nan);
  // Relative parameters: each column times the parameter's size, so that a
  // bulk modulus in Pa and a mass in kg are compared alike.
  Eigen::VectorXd size(k);
  for (Eigen::Index j = 0; j < k; ++j) size(j) = size_of(estimate(j));

  // Directions the data do not see: a parameter with weight in one of them
  // is not determined (a column of zeros, or one another column repeats).
  std::vector<bool> in(static_cast<size_t>(k), true);
  const Eigen::MatrixXd scaled = J * size.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double largest = sv.size() > 0 ? sv(0) : 0.0;
  for (Eigen::Index i = 0; i < sv.size(); ++i) {
    if (largest > 0.0 && sv(i) > kSingularRatio * largest) continue;
    for (Eigen::Index j = 0; j < k; ++j)
      if (std::abs(svd.matrixV()(j, i)) > 0.1 && in[static_cast<size_t>(j)]) {
        in[static_cast<size_t>(j)] = false;
        out.parameters[static_cast<size_t>(j)].why =
            largest == 0.0 || scaled.col(j).norm() <= kSingularRatio * largest
                ? "the measured columns do not depend on it"
                : "the measured columns depend on it only as they depend on the others together";
      }
  }
  // The covariance of the determined ones (the others held), then those whose
  // interval is as wide as their value are let go too, and the rest again.
  const double dof_scale =
      sigmas_estimated && n > k ? static_cast<double>(n) / static_cast<double>(n - k) : 1.0;
  for (;;) {
    std::vector<Eigen::Index> kept;
    for (Eigen::Index j = 0; j < k; ++j)
      if (in[static_cast<size_t>(j)]) kept.push_back(j);
    const auto m = static_cast<Eigen::Index>(kept.size());
    Eigen::MatrixXd Js(n, m);
    for (Eigen::Index a = 0; a < m; ++a) Js.col(a) = scaled.col(kept[static_cast<size_t>(a)]);
    Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(m, m);
    if (m > 0) {
      const Eigen::MatrixXd normal = Js.transpose() * Js;
      cov = normal.ldlt().solve(Eigen::MatrixXd::Identity(m, m)) * dof_scale;
    }
    bool dropped = false;
    for (Eigen::Index a = 0; a < m; ++a) {
      const Eigen::Index j = kept[static_cast<size_t>(a)];
      const double relative = std::sqrt(std::max(cov(a, a), 0.0));
      // A parameter started at 0 (an angle, an offset) has no size of its
      // own to hold its error against: its directions alone judge it.
      if (initial(j) != 0.0 &&
          !(relative * size(j) <= kLargestRelativeError * std::abs(estimate(j)))) {
        in[static_cast<size_t>(j)] = false;
        out.parameters[static_cast<size_t>(j)].why =
            "the data determine it only to +-" +
            std::to_string(
                static_cast<int>(std::round(100.0 * relative * size(j) / size_of(estimate(j))))) +
            " % (one standard error)";
        dropped = true;
      }
    }
    if (dropped) continue;
    for (Eigen::Index a = 0; a < m; ++a) {
      const Eigen::Index j = kept[static_cast<size_t>(a)];
      ParameterStatistics& s = out.parameters[static_cast<size_t>(j)];
      s.std_error = std::sqrt(cov(a, a)) * size(j);
      s.ci_low = estimate(j) - kNormal975 * s.std_error;
      s.ci_high = estimate(j) + kNormal975 * s.std_error;
      for (Eigen::Index b = 0; b < m; ++b)
        out.correlation(j, kept[static_cast<size_t>(b)]) =
            cov(a, b) / std::sqrt(cov(a, a) * cov(b, b));
    }
    break;
  }
  for (Eigen::Index j = 0; j < k; ++j) {
    ParameterStatistics& s = out.parameters[static_cast<size_t>(j)];
    s.identifiable = in[static_cast<size_t>(j)];
    if (!s.identifiable) s.std_error = s.ci_low = s.ci_high = nan;
  }
  return out;
}

}  // namespace mh::cli
