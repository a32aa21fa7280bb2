#include "solver/newton.hpp"

#include <algorithm>
#include <cmath>

namespace mh {
namespace {

// The damped step along du (NewtonDamping): on return the iterate has moved
// by the accepted lambda du, now in damping.trial, and f is its residual.
// Returns lambda, or 0 when none down to 2^-max_halvings passed the test (the
// iterate is back where it was, f the residual of the last trial).
double damped_step(NewtonProblem& problem, NewtonDamping& damping, const Eigen::VectorXd& du,
                   Eigen::VectorXd& f, NewtonOutcome& out) {
  int unused = 0;
  const double full = problem.measure(du, unused);
  // An increment within tolerance is taken whole: the test would weigh it
  // against the round-off of its own correction.
  if (full <= 1.0) {
    damping.trial = du;
    problem.add(damping.trial);
    problem.residual(f);
    return 1.0;
  }
  double lambda = 1.0;
  for (int halvings = 0; halvings <= damping.max_halvings; ++halvings, lambda *= 0.5) {
    damping.trial = lambda * du;
    problem.add(damping.trial);
    problem.residual(f);
    if (f.allFinite()) {
      problem.solve(f, damping.correction);  // the simplified increment
      if (problem.measure(damping.correction, unused) <= (1.0 - 0.25 * lambda) * full) {
        if (lambda < 1.0) ++out.damped;
        out.smallest_factor = std::min(out.smallest_factor, lambda);
        return lambda;
      }
    }
    problem.subtract(damping.trial);
  }
  return 0.0;
}

}  // namespace

NewtonOutcome newton_iterate(NewtonProblem& problem, int max_iterations, Eigen::VectorXd& f,
                             Eigen::VectorXd& du, NewtonDamping* damping) {
  NewtonOutcome out;
  problem.residual(f);
  if (problem.solved(f)) {
    out.end = NewtonOutcome::End::converged;
    return out;
  }
  for (int its = 0; its < max_iterations; ++its) {
    if (!f.allFinite()) {
      while (out.row < f.size() && std::isfinite(f[out.row])) ++out.row;
      out.end = NewtonOutcome::End::not_finite;
      return out;
    }
    if (problem.needs_setup()) problem.setup();
    problem.solve(f, du);  // Eq. (37) for the time step
    bool full_step = true;
    if (damping != nullptr) {
      const double lambda = damped_step(problem, *damping, du, f, out);
      if (lambda == 0.0) {
        out.size = problem.measure(du, out.worst);
        out.end = NewtonOutcome::End::no_descent;
        return out;
      }
      full_step = lambda == 1.0;
    } else {
      problem.add(du);
    }
    const Eigen::VectorXd& taken = damping != nullptr ? damping->trial : du;
    ++out.iterations;
    out.size = problem.measure(taken, out.worst);
    if (!problem.keep(out.size)) {
      problem.subtract(taken);
      if (damping != nullptr) problem.residual(f);  // f was the trial's
      continue;  // otherwise f is still the residual of the iterate restored
    }
    if (damping == nullptr) {
      problem.accepted();
      problem.residual(f);
    } else if (problem.accepted()) {
      problem.residual(f);
    }
    // A shortened increment says nothing of convergence: only a full one is tested.
    if ((full_step && problem.converged(out.size)) || problem.solved(f)) {
      out.end = NewtonOutcome::End::converged;
      return out;
    }
    if (problem.stop_early(its)) {
      out.end = NewtonOutcome::End::stopped;
      return out;
    }
  }
  out.end = NewtonOutcome::End::not_converged;
  return out;
}

}  // namespace mh
