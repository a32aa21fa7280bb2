// The monolithic implicit trapezoidal step (Sect. 4): positions (through the
// formulation) and subsystem states are the primary unknowns of one
// Newton-Raphson iteration (Eq. 37) whose sparse tangent KLU solves.
#include <Eigen/LU>
#include <cmath>

#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

SimulationError::SimulationError(double t, long step, const std::string& reason)
    : std::runtime_error("t = " + short_number(t) + " s, step " + std::to_string(step) + ": " +
                         reason),
      t_(t),
      step_(step),
      reason_(reason) {}

void Simulation::Engine::fail(const std::string& reason) const {
  throw SimulationError(attempt_t, attempt_step, reason);
}

std::string Simulation::Engine::status_reason(mh_status s, const std::string& what) const {
  std::string reason = what + (s == MH_DISCARD ? " was discarded" : " failed");
  if (!last_plugin_error.empty()) reason += ": " + last_plugin_error;
  return reason;
}

std::string Simulation::Engine::unknown_name(int i) const {
  if (i >= n_m) return "state '" + state_names[static_cast<size_t>(i - n_m)] + "'";
  return "mechanical unknown " + std::to_string(i + 1) + " of formulation '" + formulation_name +
         "'";
}

// Consistent initial state: the formulation's z0, zd0, zdd0; the subsystem
// rates ydot0 that make every state row vanish at t = 0.
void Simulation::Engine::start() {
  t = 0.0;
  step = 0;
  attempt_t = 0.0;
  attempt_step = 0;
  const double dt = settings.dt;
  if (!(dt > 0.0) || !std::isfinite(dt)) fail("the time step must be positive and finite");
  ydot.setZero(n_s);
  y_hat.setZero(n_s);
  scratch_rows.setZero(n_s);
  outputs.setZero(n_o);
  z = z0;  // assembled: Phi(z0) = 0, Phi_z zd0 = 0
  zd = zd0;
  zdd.setZero(N);
  Eigen::VectorXd tol_m(n_m);
  tol_m.setConstant(settings.tol_position);
  last_plugin_error.clear();
  // Algebraic states, and the equilibrium the model asks for, before the
  // formulation computes its initial accelerations from them.
  solve_algebraic_and_equilibrium();
  next_event = 0;
  while (next_event < time_events.size() && time_events[next_event] <= 0.0) ++next_event;
  mh_status st = formulation->start(formulation, t, dt, z.data(), zd.data(), tol_m.data());
  if (st >= MH_DISCARD) fail(status_reason(st, "formulation start"));
  st = formulation->coordinates(formulation, z.data(), zd.data(), zdd.data());
  if (st >= MH_DISCARD) fail(status_reason(st, "formulation coordinates"));
  tol.resize(n);
  tol.head(n_m) = tol_m;
  tol.tail(n_s) = state_tol;
  for (int i = 0; i < n; ++i)
    if (!(tol[i] > 0.0)) fail("the tolerance of " + unknown_name(i) + " is not positive");

  // ydot0: the rates that make every state row vanish at t = 0.
  forward_kinematics(model, data, z, zd);
  solve_initial_rates(t);
  y_k = y;
  ydot_k = ydot;
  // The energy bookkeeping's starting values.
  reset_applied_forces(model, data);
  evaluate_subsystems(t, scratch_rows.data());
  power_k = power;
  outputs_k = outputs;
  energy_terms(stored0, dissipation_k);
  stored = stored0;
  dissipated = 0.0;
  ke0 = mh::kinetic_energy(model, data);
  pe0 = mh::potential_energy(model, data);
  ke = ke0;
  pe = pe0;
  work = 0.0;
  phi_norm = 0.0;
  if (m > 0) {
    evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
    phi_norm = phi.norm();
  }
  started = true;
}

void Simulation::Engine::step_once() {
  if (!started) fail("step() before start()");
  const double dt = settings.dt;
  // t from the step count, not by summing dt: no round-off creep over 1e4 steps.
  const double t_next = static_cast<double>(step + 1) * dt;
  attempt_t = t_next;  // failures name the step being attempted
  attempt_step = step + 1;
  last_plugin_error.clear();
  stats.iterations = 0;
  stats.increment_norms.clear();
  stats.residual_norms.clear();

  // A time event inside the step, or at its end: the end is evaluated at the
  // event's left limit, and the rates restart after it (right limit).
  bool event = false;
  double t_eval = t_next;
  while (next_event < time_events.size() && time_events[next_event] <= t_next + 1e-9 * dt) {
    event = true;
    if (std::abs(time_events[next_event] - t_next) <= 1e-9 * dt)
      t_eval = std::nextafter(time_events[next_event], -HUGE_VAL);
    ++next_event;
  }

  // Predictor: the formulation's for its unknowns, y + dt ydot for the states
  // (y for the algebraic ones, whose rates mean nothing).
  mh_status st = formulation->predict(formulation, t_next, x.data());
  if (st >= MH_DISCARD) fail(status_reason(st, "formulation predict"));
  x.tail(n_s) = y_k + dt * ydot_k;
  for (int i = 0; i < n_s; ++i)
    if (algebraic[static_cast<size_t>(i)] != 0) x[n_m + i] = y_k[i];
  y_hat = -((2.0 / dt) * y_k + ydot_k);  // Eq. (34)

  st = residual(t_eval, x, r);
  if (st >= MH_DISCARD) fail(status_reason(st, "residual evaluation"));
  stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
  bool converged = false;
  double worst = 0.0;
  int worst_i = 0;
  while (stats.iterations < settings.max_iterations) {
    if (!r.allFinite()) {
      int bad = 0;
      while (bad < n && std::isfinite(r[bad])) ++bad;
      fail("the residual is not finite in the row of " + unknown_name(bad));
    }
    st = assemble_tangent(t_eval);
    if (st >= MH_DISCARD) fail(status_reason(st, "tangent assembly"));
    if (!klu->factor(values.data())) fail(klu->error());
    dx = -r;
    klu->solve(dx.data());  // Eq. (37)
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
    if (formulation->iteration_done != nullptr) {
      st = formulation->iteration_done(formulation, t_next, x.data());
      if (st >= MH_DISCARD) fail(status_reason(st, "formulation iteration"));
    }
    st = residual(t_eval, x, r);
    if (st >= MH_DISCARD) fail(status_reason(st, "residual evaluation"));
    stats.residual_norms.push_back(r.lpNorm<Eigen::Infinity>());
    if (worst <= 1.0) {
      converged = true;
      break;
    }
  }
  if (!converged) {
    fail("Newton did not converge in " + std::to_string(settings.max_iterations) +
         " iterations; the largest increment was " + short_number(worst) +
         " times the tolerance, in " + unknown_name(worst_i));
  }

  // Accept: the last residual call evaluated the converged iterate.
  st = formulation->accept(formulation, t_next, x.data());
  if (st >= MH_DISCARD) fail(status_reason(st, "formulation accept"));
  st = formulation->coordinates(formulation, z.data(), zd.data(), zdd.data());
  if (st >= MH_DISCARD) fail(status_reason(st, "formulation coordinates"));
  y = x.tail(n_s);
  ydot = (2.0 / dt) * y + y_hat;  // Eq. (33)
  for (int i = 0; i < n_s; ++i)
    if (algebraic[static_cast<size_t>(i)] != 0) ydot[i] = 0.0;
  outputs_k = outputs;                   // of the converged iterate's evaluation
  work += 0.5 * dt * (power_k + power);  // W = integral of F . v, trapezoidal
  power_k = power;
  double dissipation = 0.0;
  energy_terms(stored, dissipation);
  dissipated += 0.5 * dt * (dissipation_k + dissipation);
  dissipation_k = dissipation;
  for (auto& s : subsystems) {
    if (s.api->accept == nullptr) continue;
    mh_subsystem_eval ev = subsystem_eval(t_next, scratch_rows.data());
    point_at(ev, s);
    st = s.api->accept(s.api, &ev);
    if (st >= MH_DISCARD) fail(status_reason(st, "subsystem accept"));
  }
  t = t_next;
  ++step;
  forward_kinematics(model, data, z, zd);
  if (event) {
    solve_initial_rates(std::nextafter(t, HUGE_VAL));
    forward_kinematics(model, data, z, zd);
  }
  y_k = y;
  ydot_k = ydot;
  ke = mh::kinetic_energy(model, data);
  pe = mh::potential_energy(model, data);
  if (m > 0) {
    evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
    phi_norm = phi.norm();
  }
}

}  // namespace mh
