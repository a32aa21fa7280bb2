#include "least_squares.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>

namespace mh::cli {

namespace {

// The whole run as one residual block: N samples, k parameter blocks of one
// value each, in relative units (the parameter over its initial size) so
// that the solver's steps and tolerances mean the same for a mass and a
// bulk modulus. One run gives the residuals and the Jacobian together; the
// last is kept, since Ceres asks for the Jacobian at a point it has just
// evaluated.
class RunResiduals final : public ceres::CostFunction {
 public:
  RunResiduals(const SampledRun& run, const Eigen::VectorXd& scale,
               const std::vector<double>& sigma)
      : run_(run), scale_(scale), sigma_(sigma) {
    set_num_residuals(static_cast<int>(run.samples().size()));
    for (Eigen::Index j = 0; j < scale.size(); ++j) mutable_parameter_block_sizes()->push_back(1);
  }

  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    const Eigen::Index k = scale_.size();
    Eigen::VectorXd p(k);
    for (Eigen::Index j = 0; j < k; ++j) p(j) = x[j][0] * scale_(j);
    if (!(has_ && p == at_)) {
      has_ = false;
      if (!run_.evaluate(p, predicted_, &J_, why_)) return false;
      at_ = p;
      has_ = true;
    }
    const Eigen::VectorXd& measured = run_.measured();
    const auto& samples = run_.samples();
    for (size_t s = 0; s < samples.size(); ++s) {
      const double w = 1.0 / sigma_[samples[s].column];
      const auto i = static_cast<Eigen::Index>(s);
      residuals[s] = (predicted_(i) - measured(i)) * w;
      if (jacobians != nullptr)
        for (Eigen::Index j = 0; j < k; ++j)
          if (jacobians[j] != nullptr) jacobians[j][s] = J_(i, j) * scale_(j) * w;
    }
    return true;
  }

  const std::string& why() const { return why_; }
  // A run already made at `p` (the fit's start): Ceres' first evaluation,
  // which asks for the Jacobian there, reuses it.
  void seed(const Eigen::VectorXd& p, const Eigen::VectorXd& predicted, const Eigen::MatrixXd& J) {
    at_ = p;
    predicted_ = predicted;
    J_ = J;
    has_ = true;
  }
  // The last run's predictions and Jacobian when it was at `p`.
  bool ran_at(const Eigen::VectorXd& p, Eigen::VectorXd& predicted, Eigen::MatrixXd& J) const {
    if (!has_ || p != at_) return false;
    predicted = predicted_;
    J = J_;
    return true;
  }

 private:
  const SampledRun& run_;
  const Eigen::VectorXd& scale_;
  const std::vector<double>& sigma_;
  mutable bool has_ = false;
  mutable Eigen::VectorXd at_, predicted_;
  mutable Eigen::MatrixXd J_;
  mutable std::string why_;
};

}  // namespace

std::vector<double> residual_rms(const SampledRun& run, const Eigen::VectorXd& predicted) {
  std::vector<double> sum(run.columns().size(), 0.0), count(run.columns().size(), 0.0);
  for (size_t s = 0; s < run.samples().size(); ++s) {
    const auto i = static_cast<Eigen::Index>(s);
    const double e = predicted(i) - run.measured()(i);
    sum[run.samples()[s].column] += e * e;
    count[run.samples()[s].column] += 1.0;
  }
  for (size_t c = 0; c < sum.size(); ++c) sum[c] = std::sqrt(sum[c] / count[c]);
  return sum;
}

FitResult fit_parameters(const SampledRun& run, const std::vector<double>& noise,
                         int max_iterations) {
  FitResult out;
  const Eigen::VectorXd& p0 = run.initial();
  const Eigen::Index k = p0.size();
  Eigen::VectorXd scale(k);
  for (Eigen::Index j = 0; j < k; ++j) scale(j) = p0(j) != 0.0 ? std::abs(p0(j)) : 1.0;

  // The initial model's predictions: the starting weights of the columns
  // without a noise level. With its Jacobian: the solver's first evaluation
  // is at the same point (one run of the model fewer in each fit).
  Eigen::MatrixXd J0;
  if (!run.evaluate(p0, out.predicted_initial, &J0, out.why)) {
    out.why = "the initial model does not run: " + out.why;
    return out;
  }
  out.sigma = noise;
  const std::vector<double> rms0 = residual_rms(run, out.predicted_initial);
  for (size_t c = 0; c < noise.size(); ++c)
    if (!(noise[c] > 0.0)) {
      out.sigmas_estimated = true;
      out.sigma[c] = rms0[c] > 0.0 ? rms0[c] : 1.0;
    }

  std::vector<double> x(static_cast<size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) x[static_cast<size_t>(j)] = p0(j) / scale(j);
  for (out.rounds = 1;; ++out.rounds) {
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    RunResiduals residuals(run, scale, out.sigma);
    // Where this round starts: the initial model, or the last round's solution.
    if (out.rounds == 1) {
      residuals.seed(p0, out.predicted_initial, J0);
    } else {
      residuals.seed(out.estimate, out.predicted, out.jacobian);
    }
    std::vector<double*> blocks(x.size());
    for (size_t j = 0; j < x.size(); ++j) blocks[j] = &x[j];
    problem.AddResidualBlock(&residuals, nullptr, blocks);
    for (Eigen::Index j = 0; j < k; ++j) {
      double* b = blocks[static_cast<size_t>(j)];
      if (std::isfinite(run.lower()(j)))
        problem.SetParameterLowerBound(b, 0, run.lower()(j) / scale(j));
      if (std::isfinite(run.upper()(j)))
        problem.SetParameterUpperBound(b, 0, run.upper()(j) / scale(j));
    }
    ceres::Solver::Options options;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = max_iterations;
    options.function_tolerance = 1e-10;
    options.gradient_tolerance = 1e-14;
    options.parameter_tolerance = 1e-8;
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    out.iterations += static_cast<int>(summary.iterations.size()) - 1;
    if (out.rounds == 1) out.initial_cost = summary.initial_cost;
    out.final_cost = summary.final_cost;
    if (summary.termination_type == ceres::FAILURE ||
        summary.termination_type == ceres::USER_FAILURE || !summary.IsSolutionUsable()) {
      out.why = summary.message + (residuals.why().empty() ? "" : " (" + residuals.why() + ")");
      return out;
    }
    if (summary.termination_type == ceres::NO_CONVERGENCE) {
      out.why = "no convergence in " + std::to_string(max_iterations) +
                " iterations (--max-iterations): " + summary.message;
      return out;
    }
    out.estimate.resize(k);
    for (Eigen::Index j = 0; j < k; ++j) out.estimate(j) = x[static_cast<size_t>(j)] * scale(j);
    if (!residuals.ran_at(out.estimate, out.predicted, out.jacobian) &&
        !run.evaluate(out.estimate, out.predicted, &out.jacobian, out.why))
      return out;
    if (!out.sigmas_estimated) break;
    // The weights of the columns without a noise level: their RMS here.
    const std::vector<double> rms = residual_rms(run, out.predicted);
    double change = 0.0;
    for (size_t c = 0; c < noise.size(); ++c)
      if (!(noise[c] > 0.0) && rms[c] > 0.0) {
        change = std::max(change, std::abs(rms[c] / out.sigma[c] - 1.0));
        out.sigma[c] = rms[c];
      }
    if (change < 0.01) break;
    if (out.rounds == 8) {
      out.why = "the columns' residual RMS (their weights) still change by " +
                std::to_string(static_cast<int>(std::round(100 * change))) + " % after 8 rounds";
      return out;
    }
  }
  // d r / d p with the final weights.
  for (size_t s = 0; s < run.samples().size(); ++s)
    out.jacobian.row(static_cast<Eigen::Index>(s)) /= out.sigma[run.samples()[s].column];
  out.solved = true;
  return out;
}

}  // namespace mh::cli
