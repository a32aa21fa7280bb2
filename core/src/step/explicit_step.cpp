// One step of an explicit integrator (integrator.h, mh_explicit_method): the integrator
// chooses stage states, the host gives it the rates f(t, x) there, and it
// combines them. The rates come from the formulation's own residual, not from
// a new operation: with x (and the velocities xd of second-order unknowns)
// held, r(x, xd, xdd) = 0 is solved by Newton for the accelerations xdd (the
// forward dynamics: penalty's M' zdd = Q', double-step's independent
// accelerations), the subsystems' rates ydot (their rows are linear in them
// for the shipped components) and the algebraic unknowns' values. The
// Jacobian in those unknowns is differenced (dense: the method is for small
// models and for showing where an explicit scheme fails), kept across stages
// and steps while Newton contracts with it.
#include <cmath>
#include <limits>

#include "engine.hpp"
#include "monohydra/cpp/unknowns.hpp"
#include "solver/newton.hpp"

namespace mh {

namespace {

// Newton on the rates converges when every increment is below this fraction
// of the unknown's scale (its x tolerance over h^2, h or 1 by kind): the
// rates are then far more accurate than one step can use ...
constexpr double kRateTolerance = 1e-6;
// ... or below this fraction of the rate itself (round-off: a stiff
// pressure's rate of 1e9 Pa/s is not known to 1e-3 Pa/s).
constexpr double kRateRelative = 1e-10;

}  // namespace

void Simulation::Engine::size_explicit() {
  if (!explicit_method) return;
  for (Eigen::VectorXd* v :
       {&work.stages.xs, &work.stages.xds, &work.stages.xdds, &work.stages.r_rates,
        &work.stages.r_rates_pert, &work.stages.rates_step, &work.stages.rate_scale})
    v->setZero(n);
  run.rates_jacobian.setZero(n, n);
  work.stages.rates_lu = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
}

namespace {

// The rates at an explicit stage: r(x, xd, xdd) = 0 for the unknown of each
// row by its kind (xdd, xd, or x itself for an algebraic one), x held, with
// a differenced dense Jacobian kept while it halves the increment.
class StageRatesProblem final : public NewtonProblem {
 public:
  StageRatesProblem(Simulation::Engine& e, double t_eval, Eigen::VectorXd& xq, Eigen::VectorXd& xdq,
                    Eigen::VectorXd& xddq)
      : e_(e), t_eval_(t_eval), xq_(xq), xdq_(xdq), xddq_(xddq) {}

  void residual(Eigen::VectorXd& f) override {
    e_.check(e_.residual_at(t_eval_, xq_, xdq_, xddq_, f), "residual evaluation");
    if (evaluated_) e_.run.last_step.residual_norms.push_back(f.lpNorm<Eigen::Infinity>());
    evaluated_ = true;
  }
  bool needs_setup() override { return !e_.run.rates_jacobian_valid; }
  void setup() override {
    for (int j = 0; j < e_.n; ++j) {
      double& u = unknown(j);
      const double saved = u;
      const double d = 1.5e-8 * std::max(std::abs(u), e_.work.stages.rate_scale[j] * 1e3);
      u = saved + d;
      e_.check(e_.residual_at(t_eval_, xq_, xdq_, xddq_, e_.work.stages.r_rates_pert),
               "residual evaluation");
      u = saved;
      e_.run.rates_jacobian.col(j) = (e_.work.stages.r_rates_pert - e_.work.stages.r_rates) / d;
    }
    e_.work.stages.rates_lu.compute(e_.run.rates_jacobian);
    e_.run.rates_jacobian_valid = true;
    ++e_.run.last_step.tangents;
  }
  void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
    du.noalias() = e_.work.stages.rates_lu.solve(f);
    du = -du;
  }
  void add(const Eigen::VectorXd& du) override {
    for (int i = 0; i < e_.n; ++i) unknown(i) += du[i];
  }
  void subtract(const Eigen::VectorXd& du) override {
    for (int i = 0; i < e_.n; ++i) unknown(i) -= du[i];
  }
  double measure(const Eigen::VectorXd& du, int& worst_i) override {
    double worst = 0.0;
    for (int i = 0; i < e_.n; ++i) {
      const double ratio = std::abs(du[i]) / (kRateTolerance * e_.work.stages.rate_scale[i] +
                                              kRateRelative * std::abs(unknown(i)));
      if (!(ratio <= worst)) {
        worst = ratio;
        worst_i = i;
      }
    }
    return worst;
  }
  bool keep(double size) override {
    ++e_.run.last_step.iterations;
    e_.run.last_step.increment_norms.push_back(size);
    return true;
  }
  // A kept Jacobian that no longer halves the increment is renewed.
  bool converged(double size) override {
    if (size <= 1.0) return true;
    if (!(size <= 0.5 * last_)) e_.run.rates_jacobian_valid = false;
    last_ = size;
    return false;
  }

 private:
  // The unknown of row i: xdd, xd or x by the kind of unknown i.
  double& unknown(int i) {
    switch (e_.registry.kinds[static_cast<size_t>(i)]) {
      case MH_UNKNOWN_SECOND_ORDER:
        return xddq_[i];
      case MH_UNKNOWN_FIRST_ORDER:
        return xdq_[i];
      default:
        return xq_[i];
    }
  }

  Simulation::Engine& e_;
  double t_eval_;
  Eigen::VectorXd &xq_, &xdq_, &xddq_;
  bool evaluated_ = false;
  double last_ = std::numeric_limits<double>::infinity();
};

}  // namespace

void Simulation::Engine::solve_rates(double t_eval, double h, Eigen::VectorXd& xq,
                                     Eigen::VectorXd& xdq, Eigen::VectorXd& xddq) {
  for (int i = 0; i < n; ++i) {
    const uint8_t k = registry.kinds[static_cast<size_t>(i)];
    work.stages.rate_scale[i] = k == MH_UNKNOWN_SECOND_ORDER  ? registry.tol[i] / (h * h)
                                : k == MH_UNKNOWN_FIRST_ORDER ? registry.tol[i] / h
                                                              : registry.tol[i];
    if (k != MH_UNKNOWN_SECOND_ORDER) xddq[i] = 0.0;
    if (k == MH_UNKNOWN_ALGEBRAIC) xdq[i] = 0.0;
  }
  StageRatesProblem problem(*this, t_eval, xq, xdq, xddq);
  const NewtonOutcome out =
      newton_iterate(problem, settings.max_iterations, work.stages.r_rates, work.stages.rates_step);
  switch (out.end) {
    case NewtonOutcome::End::converged:
    case NewtonOutcome::End::stopped:
      return;
    case NewtonOutcome::End::not_finite:
      fail_step("the residual is not finite in the row of " + unknown_name(out.row) +
                " at an explicit stage (t = " + short_number(t_eval) + " s)");
    case NewtonOutcome::End::no_descent:  // undamped: never
    case NewtonOutcome::End::not_converged:
      break;
  }
  fail_step("the rates at an explicit stage (t = " + short_number(t_eval) +
            " s) did not converge in " + std::to_string(settings.max_iterations) +
            " Newton iterations; the largest increment was " + short_number(out.size) +
            " times its tolerance, in the rate (or value) of " + unknown_name(out.worst));
}

// The step from the accepted t by h: the integrator's stages, each with the
// rates there, then its end state and the rates there (the step's record, as
// the last Newton iterate is for an implicit step).
void Simulation::Engine::explicit_attempt(double t_eval, double h) {
  // The formulations' projections (Eqs. 20-21) weigh velocity against
  // position corrections by the map's coefficients; an explicit step hands
  // them the trapezoidal rule's for its h.
  mh_step_coefficients& c = work.map_ws.map.coefficients;
  c.struct_size = sizeof(c);
  c.h = h;
  c.dxd_dx_second = 2.0 / h;
  c.dxdd_dx_second = 4.0 / (h * h);
  c.dxd_dx_first = 2.0 / h;
  if (run.stability_due || run.accepted.step >= run.stability_next_step)
    check_explicit_stability(h);
  const uint32_t num_stages = explicit_ops.num_stages;
  for (uint32_t s = 0; s < num_stages; ++s) {
    work.stages.xs = run.x;  // guesses: the accepted values
    work.stages.xds = run.xd;
    work.stages.xdds = run.xdd;
    double t_stage = run.accepted.t;
    // The integrator's status, named only when it failed (Engine::check):
    // no string is built on the step's path.
    check(in_flight(*integrator_host, InstanceHost::Op::stage_state,
                    [&] {
                      const mh_unknown_buffers out =
                          monohydra::unknown_buffers(static_cast<size_t>(n), work.stages.xs.data(),
                                                     work.stages.xds.data(), nullptr);
                      return explicit_ops.stage_state(integrator.self, s, h, &t_stage, &out);
                    }),
          "integrator", integrator_name, "stage_state");
    if (!(t_stage >= run.accepted.t && t_stage <= run.accepted.t + h))
      fail("integrator '" + integrator_name + "' put stage " + std::to_string(s) +
           " at t = " + short_number(t_stage) + " s, outside the step [" +
           short_number(run.accepted.t) + ", " + short_number(run.accepted.t + h) + "] s");
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(work.stages.xs[i]) || !std::isfinite(work.stages.xds[i]))
        fail("the explicit integrator '" + integrator_name + "' diverged at stage " +
             std::to_string(s) + ": " + unknown_name(i) + " is not finite (h = " + short_number(h) +
             " s; a smaller step may be within its stability bound)");
    // A stage has no map: its coefficients are h alone (formulation.h).
    formulation_begin_step(monohydra::step_coefficients(h, 0.0, 0.0, 0.0), t_stage, work.stages.xs,
                           work.stages.xds, work.stages.xdds);
    solve_rates(std::min(t_stage, t_eval), h, work.stages.xs, work.stages.xds, work.stages.xdds);
    check(in_flight(*integrator_host, InstanceHost::Op::stage_rates,
                    [&] {
                      const mh_unknown_values solved = monohydra::unknown_values(
                          t_stage, static_cast<size_t>(n), work.stages.xs.data(),
                          work.stages.xds.data(), work.stages.xdds.data());
                      return explicit_ops.stage_rates(integrator.self, s, &solved);
                    }),
          "integrator", integrator_name, "stage_rates");
  }
  check(in_flight(*integrator_host, InstanceHost::Op::finish_step,
                  [&] {
                    const mh_unknown_buffers out = monohydra::unknown_buffers(
                        static_cast<size_t>(n), run.x.data(), run.xd.data(), nullptr);
                    return explicit_ops.finish_step(integrator.self, h, &out);
                  }),
        "integrator", integrator_name, "finish_step");
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(run.x[i]) || !std::isfinite(run.xd[i]))
      fail("the explicit integrator '" + integrator_name + "' diverged: " + unknown_name(i) +
           " is not finite at the step's end (h = " + short_number(h) +
           " s; a smaller step may be within its stability bound)");
  solve_rates(t_eval, h, run.x, run.xd, run.xdd);
}

}  // namespace mh
