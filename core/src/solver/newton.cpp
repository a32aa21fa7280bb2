#include "solver/newton.hpp"

#include <cmath>

namespace mh {

NewtonOutcome newton_iterate(NewtonProblem& problem, int max_iterations, Eigen::VectorXd& f,
                             Eigen::VectorXd& du) {
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
    problem.add(du);
    ++out.iterations;
    out.size = problem.measure(du, out.worst);
    if (!problem.keep(out.size)) {  // f is still the residual of the iterate restored
      problem.subtract(du);
      continue;
    }
    problem.accepted();
    problem.residual(f);
    if (problem.converged(out.size) || problem.solved(f)) {
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
