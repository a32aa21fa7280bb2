// The explicit step's stability check (explicit_stability.hpp): the
// integrator's amplification factor from its own stage operations, and the
// engine's linearisation of the rates it solves for, checked before the
// first explicit step, after every restart (time events, redefined unknowns)
// and every kStabilityInterval steps.
#include "monohydra/core/explicit_stability.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "engine.hpp"
#include "monohydra/cpp/unknowns.hpp"
#include "plugins/abi_struct.hpp"

namespace mh {

namespace {

// The test equation's two first-order unknowns.
constexpr uint8_t kTestKinds[2] = {MH_UNKNOWN_FIRST_ORDER, MH_UNKNOWN_FIRST_ORDER};

void require(mh_status s, const char* op) {
  const int v = static_cast<int>(s);
  if (v != MH_OK && v != MH_WARNING)
    throw std::runtime_error(std::string("the integrator's ") + op +
                             " failed on the linear test equation y' = lambda y");
}

double cpu_now() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

}  // namespace

StageAmplification::StageAmplification(const mh_integrator* instance)
    : self_(instance), ops_(read_struct(instance)), stages_(read_struct(ops_.explicit_method)) {}

StageAmplification::~StageAmplification() {
  if (self_ != nullptr && ops_.destroy != nullptr) ops_.destroy(self_);
}

void StageAmplification::set_up(double h) {
  mh_integrator_problem problem{};
  problem.struct_size = sizeof(problem);
  problem.num_unknowns = 2;
  problem.kinds = kTestKinds;
  problem.t0 = 0.0;
  problem.dt = h;
  require(ops_.setup(self_, &problem), "setup");
  setup_h_ = h;
}

std::complex<double> StageAmplification::factor(std::complex<double> lambda, double h) {
  if (setup_h_ == 0.0) set_up(h);
  const double a = lambda.real();
  const double b = lambda.imag();
  std::array<double, 2> x{1.0, 0.0};
  std::array<double, 2> xd{a, b};
  std::array<double, 2> xdd{0.0, 0.0};
  const mh_unknown_values at = monohydra::unknown_values(0.0, 2, x.data(), xd.data(), xdd.data());
  const mh_unknown_buffers out = monohydra::unknown_buffers(2, x.data(), xd.data(), nullptr);
  require(ops_.restart(self_, &at), "restart");
  for (uint32_t s = 0; s < stages_.num_stages; ++s) {
    double t_stage = 0.0;
    require(stages_.stage_state(self_, s, h, &t_stage, &out), "stage_state");
    xd = {a * x[0] - b * x[1], b * x[0] + a * x[1]};  // u' = A u
    mh_unknown_values solved = at;
    solved.t = t_stage;
    require(stages_.stage_rates(self_, s, &solved), "stage_rates");
  }
  require(stages_.finish_step(self_, h, &out), "finish_step");
  return {x[0], x[1]};
}

double StageAmplification::excess(std::complex<double> lambda, double h) {
  const double exact = std::exp(h * lambda.real());  // |exp(h lambda)|
  return std::abs(factor(lambda, h)) / std::max(1.0, exact);
}

double StageAmplification::largest_stable_step(const std::vector<std::complex<double>>& eigenvalues,
                                               double h0) {
  const auto stable = [&](double h) {
    for (const auto& l : eigenvalues)
      if (!(excess(l, h) <= 1.0 + kAmplificationTolerance)) return false;
    return true;
  };
  double lo = 0.0;
  double hi = h0;
  if (stable(h0)) {
    lo = h0;
    for (int k = 0;; ++k) {
      if (k == 40) return std::numeric_limits<double>::infinity();
      hi = 2.0 * lo;
      if (!stable(hi)) break;
      lo = hi;
    }
  } else {
    for (int k = 0; k < 60 && lo == 0.0; ++k) {
      const double h = hi / 2.0;
      if (stable(h))
        lo = h;
      else
        hi = h;
    }
    if (lo == 0.0) return 0.0;
  }
  while (hi - lo > 1e-4 * lo) {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return lo;
}

// The eigenvalues of d(rates)/d(state) at the accepted state, the state being
// x and xd of second-order unknowns and x of first-order ones, and the rates
// xd, xdd and xd the stages solve for (algebraic unknowns solved, not
// integrated). Central differences of solve_rates, each from the accepted
// solution, with the formulation's begin_step at every perturbed state as at
// a stage.
std::vector<std::complex<double>> Simulation::Engine::rates_eigenvalues(double t_eval, double h) {
  struct Entry {
    int i;
    bool velocity;
  };
  std::vector<Entry> entries;
  for (int i = 0; i < n; ++i) {
    const uint8_t k = registry.kinds[static_cast<size_t>(i)];
    if (k == MH_UNKNOWN_ALGEBRAIC) continue;
    entries.push_back({i, false});
    if (k == MH_UNKNOWN_SECOND_ORDER) entries.push_back({i, true});
  }
  const auto size = static_cast<Eigen::Index>(entries.size());
  Eigen::MatrixXd jacobian(size, size);
  Eigen::VectorXd plus(size);
  const auto rates_at = [&](Eigen::Index j, double delta, Eigen::VectorXd& out) {
    work.stages.xs = run.x;
    work.stages.xds = run.xd;
    work.stages.xdds = run.xdd;
    if (j >= 0) (entries[j].velocity ? work.stages.xds : work.stages.xs)[entries[j].i] += delta;
    formulation_begin_step(monohydra::step_coefficients(h, 0.0, 0.0, 0.0), t_eval, work.stages.xs,
                           work.stages.xds, work.stages.xdds);
    solve_rates(t_eval, h, work.stages.xs, work.stages.xds, work.stages.xdds);
    for (Eigen::Index row = 0; row < size; ++row) {
      const Entry& e = entries[row];
      out[row] = e.velocity ? work.stages.xdds[e.i] : work.stages.xds[e.i];
    }
  };
  Eigen::VectorXd minus(size);
  for (Eigen::Index j = 0; j < size; ++j) {
    const Entry& e = entries[j];
    // A value's step: 1e-6 of it, or of 1e4 times its tolerance; a
    // velocity's: 1e-6 of it, or the one that moves its value by the value's
    // step over h. Large enough that the rates' response stands far above
    // their round-off (a velocity at rest with a tolerance of 1e-10 m would
    // otherwise be stepped by 1e-12 m/s); central differences keep the
    // linearisation's error second order in them.
    const double step_x = 1e-6 * std::max(std::abs(run.x[e.i]), 1e4 * registry.tol[e.i]);
    const double delta = e.velocity ? std::max(1e-6 * std::abs(run.xd[e.i]), step_x / h) : step_x;
    rates_at(j, delta, plus);
    rates_at(j, -delta, minus);
    jacobian.col(j) = (plus - minus) / (2.0 * delta);
  }
  std::vector<std::complex<double>> out;
  if (size == 0) return out;
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(jacobian, false);
  if (eigen.info() != Eigen::Success)
    fail("the stability check of the explicit integrator '" + integrator_name +
         "' could not find the eigenvalues of its rates' Jacobian");
  for (Eigen::Index k = 0; k < size; ++k) out.push_back(eigen.eigenvalues()[k]);
  return out;
}

void Simulation::Engine::check_explicit_stability(double h) {
  run.stability_due = false;
  run.stability_next_step = run.accepted.step + work.stages.kStabilityInterval;
  if (settings.explicit_stability == ExplicitStabilityPolicy::off || !work.stages.amplification)
    return;
  const double cpu0 = cpu_now();
  // The check only looks: its rate solves leave the step's statistics and
  // the rates' kept Jacobian as they were (a fresh Jacobian every check
  // would change how the step's Newton converges, and so its results).
  const StepStats kept = run.last_step;
  const Eigen::MatrixXd kept_jacobian = run.rates_jacobian;
  const Eigen::PartialPivLU<Eigen::MatrixXd> kept_lu = work.stages.rates_lu;
  const bool kept_valid = run.rates_jacobian_valid;
  std::vector<std::complex<double>> eigenvalues;
  bool linearised = true;
  try {
    eigenvalues = rates_eigenvalues(run.accepted.t, h);
  } catch (const SimulationError&) {
    // A rate solve at a perturbed state failed (Newton on the rates near a
    // throttle's zero pressure drop): this check is skipped, the step goes
    // on as it would without it, and the next check is due as usual.
    linearised = false;
  }
  run.last_step = kept;
  run.rates_jacobian = kept_jacobian;
  work.stages.rates_lu = kept_lu;
  run.rates_jacobian_valid = kept_valid;
  reports.last_plugin_error.clear();
  if (!linearised) {
    ++run.stability.skipped;
    run.stability.cpu_seconds += cpu_now() - cpu0;
    return;
  }
  double worst = 0.0;
  std::complex<double> worst_lambda;
  try {
    for (const auto& l : eigenvalues) {
      const double e = work.stages.amplification->excess(l, h);
      if (!(e <= worst)) {
        worst = e;
        worst_lambda = l;
      }
    }
    const double stable_dt = work.stages.amplification->largest_stable_step(eigenvalues, h);
    run.stability.stable_dt = std::min(run.stability.stable_dt, stable_dt);
  } catch (const std::runtime_error& err) {
    fail(std::string(err.what()) + " (integrator '" + integrator_name + "')");
  }
  ++run.stability.checks;
  const bool unstable = worst > 1.0 + kAmplificationTolerance;
  if (run.stability.checks == 1 || worst > run.stability_worst_excess) {
    run.stability_worst_excess = worst;
    run.stability.t = run.accepted.t;
    run.stability.step = run.accepted.step + 1;
    run.stability.h = h;
    run.stability.eigenvalue = worst_lambda;
    run.stability.amplification = std::abs(work.stages.amplification->factor(worst_lambda, h));
  }
  run.stability.unstable = run.stability.unstable || unstable;
  run.stability.cpu_seconds += cpu_now() - cpu0;
  if (unstable && settings.explicit_stability == ExplicitStabilityPolicy::error)
    fail(  // the worst check is this one: the first unstable one stops the run
        "the explicit integrator '" + integrator_name + "' is unstable at h = " + short_number(h) +
        " s: the mode lambda = " + short_number(worst_lambda.real()) +
        (worst_lambda.imag() < 0 ? " - " : " + ") + short_number(std::abs(worst_lambda.imag())) +
        "i 1/s has |R(h lambda)| = " + short_number(run.stability.amplification) +
        " > 1; stable below h ~ " + short_number(run.stability.stable_dt) +
        " s (solver.explicit_stability: error)");
}

}  // namespace mh
