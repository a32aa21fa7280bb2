// One step of the monolithic implicit scheme (Sect. 4): the integrator's
// prediction, the Newton iteration over every unknown (newton_solve.cpp), and
// the acceptance that the formulation may correct (the projections of Eqs.
// 20-21) and the integrator's history follows. Time events restart the
// integrator at their right limit.
#include <algorithm>
#include <cmath>

#include "engine.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

SimulationError::SimulationError(double t, long step, const std::string& reason)
    : std::runtime_error("t = " + short_number(t) + " s, step " + std::to_string(step) + ": " +
                         reason),
      t_(t),
      step_(step),
      reason_(reason) {}

void Simulation::Engine::fail(const std::string& reason) const {
  throw SimulationError(run.accepted.attempt_t, run.accepted.attempt_step, reason);
}

void Simulation::Engine::fail_step(const std::string& reason) const {
  throw StepFailure(run.accepted.attempt_t, run.accepted.attempt_step, reason);
}

void Simulation::Engine::fail_nonfinite(double value, size_t index, const InstanceHost& writer,
                                        const char* call, const char* what, bool retryable) const {
  const std::string reason = nonfinite_reason(value, index, writer, call, what);
  if (retryable) fail_step(reason);
  fail(reason);
}

void Simulation::Engine::fail_overrun(GuardedArray& array, const InstanceHost& writer,
                                      const char* call, const char* what) const {
  array.arm();
  fail((writer.label.empty() ? writer.source : writer.label) + " wrote past the end of its " +
       what + " (" + std::to_string(array.size()) + " entries) in " + call);
}

std::string Simulation::Engine::nonfinite_reason(double value, size_t index,
                                                 const InstanceHost& writer, const char* call,
                                                 const char* what) const {
  return (writer.label.empty() ? writer.source : writer.label) + " wrote a non-finite value (" +
         short_number(value) + ") in " + call + ": " + what + " entry " + std::to_string(index);
}

void Simulation::Engine::check_outputs(const char* when) const {
  for (int i = 0; i < n_o; ++i) {
    const double v = registry.outputs[i];
    if (std::isfinite(v)) continue;
    // The owner is the qualified name's prefix: an instance, or the formulation.
    const VariableInfo& info = registry.output_info[static_cast<size_t>(i)];
    const std::string owner = info.qualified.substr(0, info.qualified.find('.'));
    const InstanceHost* writer = formulation_host.get();
    const char* call = "write_outputs";
    for (const SubsystemInstance& s : subsystems)
      if (s.spec->name == owner && owner != formulation_name) {
        writer = s.host.get();
        call = "evaluate";
      }
    const std::string what = std::string("output '") + info.qualified + "' " + when + ", outputs";
    fail_nonfinite(v, static_cast<size_t>(i), *writer, call, what.c_str(), false);
  }
}

std::string Simulation::Engine::status_reason(mh_status s, const std::string& what) const {
  const int v = static_cast<int>(s);
  std::string reason = what;
  if (v < MH_OK || v > MH_FATAL)
    reason += " returned the unknown status " + std::to_string(v) + " (taken as an error)";
  else if (v == MH_DISCARD)
    reason += " was discarded";
  else if (v == MH_FATAL)
    reason += " failed fatally";
  else
    reason += " failed";
  if (!reports.last_plugin_error.empty()) reason += ": " + reports.last_plugin_error;
  return reason;
}

std::string Simulation::Engine::unknown_name(int i) const {
  if (i >= n_m) return "state '" + states.state_info[static_cast<size_t>(i - n_m)].qualified + "'";
  return "unknown '" + registry.unknown_names[static_cast<size_t>(i)] + "' of formulation '" +
         formulation_name + "'";
}

// Consistent initial state: the formulation's x0, xd0, xdd0 (and so z0, zd0,
// zdd0); the subsystem rates ydot0 that make every state row vanish at t = 0;
// the integrator started from them.
void Simulation::Engine::start() {
  if (sens.active) {
    start_sensitivities();  // forward_sensitivities.cpp: start_run() three times per parameter
    return;
  }
  start_run();
}

void Simulation::Engine::start_run() {
  run.accepted.t = 0.0;
  run.accepted.step = 0;
  run.accepted.attempt_t = 0.0;
  run.accepted.attempt_step = 0;
  states.ydot.setZero(n_s);
  work.eval.scratch_rows.setZero(n_s);
  registry.outputs.setZero(n_o);
  run.accepted.z = cons.z0;  // assembled: Phi(z0) = 0, Phi_z zd0 = 0
  run.accepted.zd = cons.zd0;
  run.accepted.zdd.setZero(N);
  reports.last_plugin_error.clear();
  run.counters = Simulation::WorkCounters{};
  // The step's statistics grow by one entry per iteration: sized here so
  // that a step allocates nothing (only a retried step may need more).
  const size_t per_attempt = static_cast<size_t>(std::max(settings.max_iterations, 1)) + 2;
  // A damped iteration evaluates the residual at each trial (NewtonDamping:
  // at most 11) and once more after the formulation's iteration_done.
  const size_t residuals_per_iteration = settings.line_search ? 12 : 1;
  run.last_step.increment_norms.reserve(4 * per_attempt);
  run.last_step.residual_norms.reserve(4 * per_attempt * residuals_per_iteration);
  // Algebraic states, and the equilibrium the model asks for, before the
  // formulation computes its initial accelerations from them.
  solve_algebraic_and_equilibrium();
  run.next_event = 0;
  while (run.next_event < states.time_events.size() && states.time_events[run.next_event] <= 0.0)
    ++run.next_event;
  run.x.setZero();
  run.xd.setZero();
  run.xdd.setZero();
  check(in_flight(*formulation_host, InstanceHost::Op::start,
                  [&] {
                    const mh_unknown_buffers out = monohydra::unknown_buffers(
                        static_cast<size_t>(n_m), run.x.data(), run.xd.data(), run.xdd.data());
                    return formulation.ops.start(formulation.self, &out);
                  }),
        "formulation start");
  const auto mech = static_cast<size_t>(n_m);
  check_finite(run.x.data(), mech, *formulation_host, "start", "x", false);
  check_finite(run.xd.data(), mech, *formulation_host, "start", "xd", false);
  check_finite(run.xdd.data(), mech, *formulation_host, "start", "xdd", false);
  check(in_flight(*formulation_host, InstanceHost::Op::coordinates,
                  [&] {
                    const mh_coordinate_buffers out{
                        sizeof(mh_coordinate_buffers), static_cast<uint32_t>(N),
                        run.accepted.z.data(), run.accepted.zd.data(), run.accepted.zdd.data()};
                    return formulation.ops.coordinates(formulation.self, &out);
                  }),
        "formulation coordinates");
  const auto coords = static_cast<size_t>(N);
  check_finite(run.accepted.z.data(), coords, *formulation_host, "coordinates", "z", false);
  check_finite(run.accepted.zd.data(), coords, *formulation_host, "coordinates", "zd", false);
  check_finite(run.accepted.zdd.data(), coords, *formulation_host, "coordinates", "zdd", false);
  registry.tol.resize(n);
  registry.tol.head(n_m) = registry.unknown_tol;
  registry.tol.tail(n_s) = states.state_tol;
  for (int i = 0; i < n; ++i)
    if (!(registry.tol[i] > 0.0)) fail("the tolerance of " + unknown_name(i) + " is not positive");

  // ydot0: the rates that make every state row vanish at t = 0.
  forward_kinematics(model, data, run.accepted.z, run.accepted.zd);
  solve_initial_rates(run.accepted.t);
  run.x.tail(n_s) = states.y;
  run.xd.tail(n_s) = states.ydot;
  for (int i = 0; i < n_s; ++i)
    if (states.algebraic[static_cast<size_t>(i)] != 0) run.xd[n_m + i] = 0.0;
  run.y = states.y;
  run.ydot = states.ydot;
  run.reuse.invalidate();
  restart_integrator();
  start_energy_balance();
  run.accepted.started = true;
}

void Simulation::Engine::step_once() {
  if (!run.accepted.started) fail("step() before start()");
  if (run.input_jump_pending) apply_input_jump();
  // t from the step count, not by summing dt: no round-off creep over 1e4 steps.
  const double t_next = static_cast<double>(run.accepted.step + 1) * settings.dt;
  run.accepted.attempt_step = run.accepted.step + 1;
  run.last_step.iterations = 0;
  run.last_step.retries = 0;
  run.last_step.tangents = 0;
  run.last_step.damped = 0;
  run.last_step.converged = true;
  run.last_step.unconverged = 0.0;
  run.last_step.increment_norms.clear();
  run.last_step.residual_norms.clear();
  advance(t_next, settings.max_step_halvings);
  ++run.accepted.step;
}

// From the accepted t to t_to in one step; when that step fails for a reason
// a shorter step may cure (Newton, a discarded evaluation) and halvings are
// left, in two halves instead. Every accepted (sub-)step is a complete step:
// the formulation, the integrator and the subsystems accept it.
void Simulation::Engine::advance(double t_to, int halvings_left) {
  const size_t events_before = run.next_event;
  try {
    attempt(t_to);
  } catch (const StepFailure& failure) {
    run.reuse.invalidate();  // modified Newton: the retry factors anew
    if (halvings_left <= 0) {
      if (run.last_step.retries == 0) throw;
      throw SimulationError(
          failure.time(), failure.step(),
          failure.reason() + " (after " + std::to_string(run.last_step.retries) +
              " halvings of the step, the most the model allows: " + "solver.max_step_halvings = " +
              std::to_string(settings.max_step_halvings) + ")");
    }
    run.next_event = events_before;
    ++run.last_step.retries;
    const double t_mid = 0.5 * (run.accepted.t + t_to);
    advance(t_mid, halvings_left - 1);
    advance(t_to, halvings_left - 1);
  }
}

// One step from the accepted t to t_next.
void Simulation::Engine::attempt(double t_next) {
  const double h = t_next - run.accepted.t;
  run.accepted.attempt_t = t_next;  // failures name the step being attempted
  // ... and so does a crash handler (plugin_call.hpp)
  plugin_call_in_flight().t.store(t_next, std::memory_order_relaxed);
  plugin_call_in_flight().step.store(run.accepted.attempt_step, std::memory_order_relaxed);
  reports.last_plugin_error.clear();

  // A time event inside the step, or at its end: the end is evaluated at the
  // event's left limit, and the integrator restarts after it (right limit).
  bool event = false;
  double t_eval = t_next;
  while (run.next_event < states.time_events.size() &&
         states.time_events[run.next_event] <= t_next + 1e-9 * h) {
    // An input's table jump is an event only while the input follows it.
    const int input = states.time_event_inputs[run.next_event];
    if (input < 0 || run.input_follows_table[static_cast<size_t>(input)] != 0) {
      event = true;
      if (std::abs(states.time_events[run.next_event] - t_next) <= 1e-9 * h)
        t_eval = std::nextafter(states.time_events[run.next_event], -HUGE_VAL);
    }
    ++run.next_event;
  }

  if (explicit_method) {
    explicit_attempt(t_eval, h);  // explicit_step.cpp: no map, no Newton over x
    accept_step(t_next, event, h, t_eval);
    return;
  }
  prepare_step(t_next, h);
  try {
    newton_solve(t_eval, t_next);
  } catch (const StepFailure&) {
    // Modified Newton may fail on a kept factorization where full Newton
    // converges: the step once more from its prediction, factoring at every
    // iteration, before the failure counts.
    if (!run.reuse.retry_with_full_newton()) throw;
    prepare_step(t_next, h);
    newton_solve(t_eval, t_next);
  }
  accept_step(t_next, event, h, t_eval);
}

// The integrator's map and prediction for the step to t_next, told to the
// formulation.
void Simulation::Engine::prepare_step(double t_next, double h) {
  begin_step(t_next, h);
  run.x = work.map_ws.x_pred;
  rates_of(run.x, run.xd, run.xdd);
  formulation_begin_step(work.map_ws.map.coefficients, t_next, run.x, run.xd, run.xdd);
}

// The formulation's begin_step (optional) with the step's coefficients and
// the prediction of its own n_m unknowns.
void Simulation::Engine::formulation_begin_step(const mh_step_coefficients& coefficients,
                                                double t_next, const Eigen::VectorXd& xq,
                                                const Eigen::VectorXd& xdq,
                                                const Eigen::VectorXd& xddq) {
  if (formulation.ops.begin_step == nullptr) return;
  mh_step_begin step{};
  step.struct_size = sizeof(step);
  step.coefficients = coefficients;
  step.predicted = monohydra::unknown_values(t_next, static_cast<size_t>(n_m), xq.data(),
                                             xdq.data(), xddq.data());
  check(in_flight(*formulation_host, InstanceHost::Op::begin_step,
                  [&] { return formulation.ops.begin_step(formulation.self, &step); }),
        "formulation begin_step");
}

// The last residual call evaluated the converged iterate: its rates, the
// subsystems' rows, powers and outputs are the step's.
void Simulation::Engine::accept_step(double t_next, bool event, double h, double t_eval) {
  if (sens.active) sensitivities_before_accept(t_eval, t_next, h);
  uint32_t flags = 0;
  check(in_flight(*formulation_host, InstanceHost::Op::accept,
                  [&] {
                    const mh_unknown_buffers values = monohydra::unknown_buffers(
                        static_cast<size_t>(n_m), run.x.data(), run.xd.data(), run.xdd.data());
                    return formulation.ops.accept(formulation.self, t_next,
                                                  &work.map_ws.map.coefficients, &values, &flags);
                  }),
        "formulation accept");
  // What accept left in x, xd, xdd (its corrections, a redefinition) is the
  // integrator's history: a non-finite value is named here, with its writer.
  const auto mech = static_cast<size_t>(n_m);
  check_finite(run.x.data(), mech, *formulation_host, "accept", "x", false);
  check_finite(run.xd.data(), mech, *formulation_host, "accept", "xd", false);
  check_finite(run.xdd.data(), mech, *formulation_host, "accept", "xdd", false);
  check(in_flight(*formulation_host, InstanceHost::Op::coordinates,
                  [&] {
                    const mh_coordinate_buffers out{
                        sizeof(mh_coordinate_buffers), static_cast<uint32_t>(N),
                        run.accepted.z.data(), run.accepted.zd.data(), run.accepted.zdd.data()};
                    return formulation.ops.coordinates(formulation.self, &out);
                  }),
        "formulation coordinates");
  const auto coords = static_cast<size_t>(N);
  check_finite(run.accepted.z.data(), coords, *formulation_host, "coordinates", "z", false);
  check_finite(run.accepted.zd.data(), coords, *formulation_host, "coordinates", "zd", false);
  check_finite(run.accepted.zdd.data(), coords, *formulation_host, "coordinates", "zdd", false);
  states.y = run.x.tail(n_s);
  states.ydot = run.xd.tail(n_s);
  if (formulation.ops.write_outputs != nullptr)
    check(in_flight(*formulation_host, InstanceHost::Op::write_outputs,
                    [&] {
                      return formulation.ops.write_outputs(
                          formulation.self, registry.outputs.data(), static_cast<uint32_t>(n_o));
                    }),
          "formulation write_outputs");
  check_outputs("at the accepted step");
  run.outputs = registry.outputs;  // of the converged iterate's evaluation
  update_energy_balance(h);
  for (auto& s : subsystems) {
    if (s.api.ops.accept == nullptr) continue;
    mh_subsystem_eval ev = subsystem_eval(t_next, work.eval.scratch_rows.data());
    point_at(ev, s);
    refresh_signals(s, ev);
    check(in_flight(*s.host, InstanceHost::Op::accept,
                    [&] { return s.api.ops.accept(s.api.self, &ev); }),
          "subsystem", s.spec->name, "accept");
  }
  run.accepted.t = t_next;
  kinematics_at(run.accepted.z.data(), run.accepted.zd.data());
  if (event) rates_after_jump();
  run.y = states.y;
  run.ydot = states.ydot;
  if (event || (flags & MH_ACCEPT_REDEFINED) != 0) {
    run.reuse.invalidate();  // x may mean something else now, or jump
    restart_integrator();
  } else {
    check(in_flight(*integrator_host, InstanceHost::Op::accept,
                    [&] {
                      const mh_unknown_values at =
                          monohydra::unknown_values(run.accepted.t, static_cast<size_t>(n),
                                                    run.x.data(), run.xd.data(), run.xdd.data());
                      return integrator.ops.accept(integrator.self, &at);
                    }),
          "integrator", integrator_name, "accept");
  }
  measure_mechanism();
  if (sens.active) sensitivities_after_accept(t_next, flags, event);
}

void Simulation::Engine::rates_after_jump() {
  solve_initial_rates(std::nextafter(run.accepted.t, HUGE_VAL));
  kinematics_at(run.accepted.z.data(), run.accepted.zd.data());
  run.xd.tail(n_s) = states.ydot;
}

// What accept_step does after a time event, for a jump between two steps:
// the accepted state keeps its coordinates and states, its rates are the
// right limit's, and the integrator starts again from there.
void Simulation::Engine::apply_input_jump() {
  run.input_jump_pending = false;
  rates_after_jump();
  run.ydot = states.ydot;
  run.reuse.invalidate();
  restart_integrator();
}

}  // namespace mh
