// The Newton-Raphson iteration of one step (Eq. 37) over every unknown at
// once, monolithically: the formulation's and the subsystem states, as a
// problem of the one Newton iteration (newton.hpp). The rates come from the
// integrator's map (integrator_map.cpp), the tangent from tangent.cpp, its
// solution from the linear solver.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine.hpp"
#include "solver/newton.hpp"

namespace mh {

namespace {

// The step's system r(x) = 0 over every unknown: the engine's residual and
// tangent, its linear solver, full or modified Newton (TangentReuse), the
// formulation's iteration_done, and real time's cap and deadline.
class StepProblem final : public NewtonProblem {
 public:
  StepProblem(Simulation::Engine& e, double t_eval, double t_next)
      : e_(e), t_eval_(t_eval), t_next_(t_next) {}

  void residual(Eigen::VectorXd& f) override {
    e_.check(e_.residual(t_eval_, e_.run.x, f), "residual evaluation");
    e_.run.last_step.residual_norms.push_back(f.lpNorm<Eigen::Infinity>());
  }
  bool needs_setup() override {
    return e_.run.reuse.needs_tangent(e_.work.map_ws.map.coefficients);
  }
  void setup() override {
    if (e_.work.solver.articulated) {
      // dxdd_dx M' at the iterate: its kinematics are the last residual's
      // (x = z, the formulation's MH_EXT_COORDINATE_UNKNOWNS).
      e_.kinematics_at(e_.run.x.data(), e_.run.xd.data());
      if (!(e_.work.map_ws.map.coefficients.dxdd_dx_second > 0.0))
        e_.fail_step(
            "solver.newton: articulated needs the integrator's map to tie the "
            "accelerations to the coordinates (dxdd_dx > 0)");
      if (!articulated_factor(e_.model, e_.data, *e_.work.solver.articulated))
        e_.fail_step(
            "the mass matrix M' is singular (a joint whose subtree has no inertia about "
            "its axis): solver.newton: articulated cannot factor it");
    } else {
      e_.check(e_.assemble_tangent(t_eval_), "tangent assembly");
      if (!e_.work.solver.linear_solver->factor(e_.work.tangent_ws.values.data()))
        e_.fail_step(e_.work.solver.linear_solver->error());
    }
    e_.run.reuse.factored(e_.work.map_ws.map.coefficients);
    ++e_.run.last_step.tangents;
  }
  void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
    du = -f;
    if (e_.work.solver
            .articulated) {  // (dxdd_dx M')^-1, Eq. (37) with the mass matrix for the tangent
      articulated_solve(e_.model, *e_.work.solver.articulated, du);
      du /= e_.work.map_ws.map.coefficients.dxdd_dx_second;
      return;
    }
    e_.work.solver.linear_solver->solve(du.data());
  }
  void add(const Eigen::VectorXd& du) override { e_.run.x += du; }
  void subtract(const Eigen::VectorXd& du) override { e_.run.x -= du; }
  double measure(const Eigen::VectorXd& du, int& worst_i) override {
    double worst = 0.0;
    for (int i = 0; i < e_.n; ++i) {
      const double ratio = std::abs(du[i]) / e_.registry.tol[i];
      if (!(ratio <= worst)) {
        worst = ratio;
        worst_i = i;
      }
    }
    return worst;
  }
  // Modified Newton: an increment of a kept factorization that grew is undone
  // and the next iteration factors anew.
  bool keep(double size) override {
    ++e_.run.last_step.iterations;
    e_.run.last_step.increment_norms.push_back(size);
    e_.run.reuse.increment(size);
    return !e_.run.reuse.diverging();
  }
  bool accepted() override {
    if (e_.formulation.ops.iteration_done == nullptr) return false;
    e_.rates_of(e_.run.x, e_.run.xd, e_.run.xdd);
    e_.check(normalized(in_flight(*e_.formulation_host, InstanceHost::Op::iteration_done,
                                  [&] {
                                    const mh_unknown_values at = monohydra::unknown_values(
                                        t_next_, static_cast<size_t>(e_.n_m), e_.run.x.data(),
                                        e_.run.xd.data(), e_.run.xdd.data());
                                    return e_.formulation.ops.iteration_done(e_.formulation.self,
                                                                             &at);
                                  })),
             "formulation iteration");
    return true;
  }
  bool converged(double size) override {
    return e_.run.reuse.converged(size, e_.work.solver.quadratic);
  }
  // Real-time mode: a late or over-long step is accepted as it stands.
  bool stop_early(int iteration) override {
    return e_.work.solver.real_time_cap > 0 &&
           (iteration + 1 >= e_.work.solver.real_time_cap ||
            std::chrono::steady_clock::now() >= e_.work.solver.step_deadline);
  }

 private:
  Simulation::Engine& e_;
  double t_eval_, t_next_;
};

}  // namespace

void Simulation::Engine::newton_solve(double t_eval, double t_next) {
  run.reuse.begin_step();
  StepProblem problem(*this, t_eval, t_next);
  // Real-time mode replaces the iteration limit by its cap, at which the step
  // is accepted rather than failed.
  const int limit =
      work.solver.real_time_cap > 0 ? work.solver.real_time_cap : settings.max_iterations;
  NewtonDamping damping{work.solver.dx_trial, work.solver.dx_correction};
  const NewtonOutcome out = newton_iterate(problem, limit, work.r, work.solver.dx,
                                           settings.line_search ? &damping : nullptr);
  run.last_step.damped += out.damped;
  switch (out.end) {
    case NewtonOutcome::End::converged:
      return;
    case NewtonOutcome::End::stopped:
      run.last_step.converged = false;
      run.last_step.unconverged = std::max(run.last_step.unconverged, out.size);
      return;
    case NewtonOutcome::End::not_finite:
      fail_step("the residual is not finite in the row of " + unknown_name(out.row) +
                ", written by " +
                (out.row < n_m ? "formulation '" + formulation_name + "'"
                               : nonfinite_source(out.row - n_m)));
    case NewtonOutcome::End::no_descent:
      fail_step(
          "Newton with line search found no step along its increment that passed the "
          "monotonicity test (down to 1/1024 of it), in iteration " +
          std::to_string(out.iterations + 1) + "; the increment was " + short_number(out.size) +
          " times the tolerance, largest in " + unknown_name(out.worst));
    case NewtonOutcome::End::not_converged:
      break;
  }
  // A matrix that is not the tangent (tangent_reuse.hpp): say so, since its
  // increments may well be within the tolerance.
  const std::string suspect =
      work.solver.quadratic && run.reuse.tangent_suspect()
          ? "; its increments shrank only by a factor of " + short_number(run.reuse.rate()) +
                " per iteration on tangents made in this step, where the residual's derivative "
                "makes them shrink quadratically: a component's Jacobian or the formulation's "
                "tangent is not the derivative of its residual (monohydra check compares them)"
          : "";
  fail_step("Newton did not converge in " + std::to_string(settings.max_iterations) +
            " iterations; the largest increment was " + short_number(out.size) +
            " times the tolerance, in " + unknown_name(out.worst) + suspect);
}

// Evaluates the subsystems one by one at the current kinematics, states and
// rates into a scratch row set, and names the first that writes a non-finite
// value into `row` (only when a step has already failed: no cost otherwise).
std::string Simulation::Engine::nonfinite_source(int row) {
  mh_subsystem_eval ev = subsystem_eval(run.accepted.attempt_t, work.eval.scratch_rows.data());
  for (auto& s : subsystems) {
    work.eval.scratch_rows.setZero();
    point_at(ev, s);
    const mh_status st = normalized(evaluate_instance(s, ev));
    if (status_ok(st) && !std::isfinite(work.eval.scratch_rows[row]))
      return "subsystem '" + s.spec->name + "' (" + s.spec->type + ")";
  }
  return "the subsystems' sum (no single instance wrote a non-finite value)";
}

}  // namespace mh
