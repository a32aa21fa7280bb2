// The Newton-Raphson iteration of one step (Eq. 37) over every unknown at
// once, monolithically: the formulation's and the subsystem states. It knows
// Newton and nothing else: the rates come from the integrator's map
// (integrator_map.cpp), the tangent from tangent.cpp, its solution from the
// linear solver.
#include <cmath>

#include "engine.hpp"

namespace mh {

void Simulation::Engine::newton_solve(double t_eval, double t_next) {
  mh_status st = residual(t_eval, x, r);
  check(st, "residual evaluation");
  stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
  double worst = 0.0;
  int worst_i = 0;
  while (stats.iterations < settings.max_iterations) {
    if (!r.allFinite()) {
      int bad = 0;
      while (bad < n && std::isfinite(r[bad])) ++bad;
      fail("the residual is not finite in the row of " + unknown_name(bad));
    }
    check(assemble_tangent(t_eval), "tangent assembly");
    if (!linear_solver->factor(values.data())) fail(linear_solver->error());
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
    if (formulation.ops.iteration_done != nullptr) {
      rates_of(x, xd, xdd);
      st = normalized(formulation.ops.iteration_done(formulation.self, t_next, x.data(), xd.data(),
                                                     xdd.data()));
      check(st, "formulation iteration");
    }
    st = residual(t_eval, x, r);
    check(st, "residual evaluation");
    stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
    if (worst <= 1.0) return;
  }
  fail("Newton did not converge in " + std::to_string(settings.max_iterations) +
       " iterations; the largest increment was " + short_number(worst) +
       " times the tolerance, in " + unknown_name(worst_i));
}

}  // namespace mh
