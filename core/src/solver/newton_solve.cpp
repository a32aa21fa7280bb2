// The Newton-Raphson iteration of one step (Eq. 37) over every unknown at
// once, monolithically: the formulation's and the subsystem states. It knows
// Newton and nothing else: the rates come from the integrator's map
// (integrator_map.cpp), the tangent from tangent.cpp, its solution from the
// linear solver.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine.hpp"

namespace mh {

void Simulation::Engine::newton_solve(double t_eval, double t_next) {
  mh_status st = residual(t_eval, x, r);
  check(st, "residual evaluation");
  stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
  double worst = 0.0;
  int worst_i = 0;
  reuse.begin_step();
  // Real-time mode replaces the iteration limit by its cap, at which the step
  // is accepted (below) rather than failed.
  const int limit = real_time_cap > 0 ? real_time_cap : settings.max_iterations;
  for (int its = 0; its < limit; ++its) {
    if (!r.allFinite()) {
      int bad = 0;
      while (bad < n && std::isfinite(r[bad])) ++bad;
      fail_step(
          "the residual is not finite in the row of " + unknown_name(bad) + ", written by " +
          (bad < n_m ? "formulation '" + formulation_name + "'" : nonfinite_source(bad - n_m)));
    }
    if (reuse.needs_tangent(map.coefficients)) {  // always, unless modified Newton
      check(assemble_tangent(t_eval), "tangent assembly");
      if (!linear_solver->factor(values.data())) fail_step(linear_solver->error());
      reuse.factored(map.coefficients);
      ++stats.tangents;
    }
    dx = -r;
    linear_solver->solve(dx.data());  // Eq. (37)
    x += dx;
    ++stats.iterations;
    worst = 0.0;
    for (int i = 0; i < n; ++i) {
      const double ratio = std::abs(dx[i]) / tol[i];
      if (!(ratio <= worst)) {
        worst = ratio;
        worst_i = i;
      }
    }
    stats.increment_norms.push_back(worst);
    reuse.increment(worst);
    if (reuse.diverging()) {  // modified Newton: back to the last iterate, a fresh tangent
      x -= dx;                // r is still its residual: no residual call since
      continue;
    }
    if (formulation.ops.iteration_done != nullptr) {
      rates_of(x, xd, xdd);
      st = normalized(formulation.ops.iteration_done(formulation.self, t_next, x.data(), xd.data(),
                                                     xdd.data()));
      check(st, "formulation iteration");
    }
    st = residual(t_eval, x, r);
    check(st, "residual evaluation");
    stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
    if (reuse.converged(worst)) return;
    // Real-time mode: a late or over-long step is accepted as it stands.
    if (real_time_cap > 0 &&
        (its + 1 >= real_time_cap || std::chrono::steady_clock::now() >= step_deadline)) {
      stats.converged = false;
      stats.unconverged = std::max(stats.unconverged, worst);
      return;
    }
  }
  fail_step("Newton did not converge in " + std::to_string(settings.max_iterations) +
            " iterations; the largest increment was " + short_number(worst) +
            " times the tolerance, in " + unknown_name(worst_i));
}

// Evaluates the subsystems one by one at the current kinematics, states and
// rates into a scratch row set, and names the first that writes a non-finite
// value into `row` (only when a step has already failed: no cost otherwise).
std::string Simulation::Engine::nonfinite_source(int row) {
  mh_subsystem_eval ev = subsystem_eval(attempt_t, scratch_rows.data());
  for (auto& s : subsystems) {
    scratch_rows.setZero();
    point_at(ev, s);
    const mh_status st = normalized(s.api.ops.evaluate(s.api.self, &ev));
    if (status_ok(st) && !std::isfinite(scratch_rows[row]))
      return "subsystem '" + s.spec->name + "' (" + s.spec->type + ")";
  }
  return "the subsystems' sum (no single instance wrote a non-finite value)";
}

}  // namespace mh
