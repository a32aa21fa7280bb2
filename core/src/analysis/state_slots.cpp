// The run's state vector X and its consistent rates (state_slots.hpp).
#include "state_slots.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <utility>

#include "monohydra/core/run_state.hpp"
#include "monohydra/cpp/unknowns.hpp"

namespace mh {

namespace {

// The consistent rates: Newton stops when every increment is below this
// fraction of the rate's scale (tolerance / h^2, / h or itself by kind).
constexpr double kRateTolerance = 1e-6;
constexpr int kRateIterations = 20;
// On a Jacobian kept from an earlier state: at most this many iterations,
// each at most this fraction of the one before, or it is factored afresh.
constexpr int kKeptIterations = 6;
constexpr double kSlowContraction = 0.5;

}  // namespace

std::vector<StateSlot> state_slots(const Simulation::Engine& e) {
  std::vector<StateSlot> slots;
  for (int i = 0; i < e.n_m; ++i)
    if (e.registry.kinds[static_cast<size_t>(i)] != MH_UNKNOWN_ALGEBRAIC)
      slots.push_back({i, false});
  for (int i = 0; i < e.n_m; ++i)
    if (e.registry.kinds[static_cast<size_t>(i)] == MH_UNKNOWN_SECOND_ORDER)
      slots.push_back({i, true});
  for (int i = e.n_m; i < e.n; ++i)
    if (e.registry.kinds[static_cast<size_t>(i)] != MH_UNKNOWN_ALGEBRAIC)
      slots.push_back({i, false});
  return slots;
}

double& slot_value(Simulation::Engine& e, const StateSlot& s) {
  return s.rate ? e.run.xd[s.unknown] : e.run.x[s.unknown];
}

double& rate_unknown(Simulation::Engine& e, int i) {
  switch (e.registry.kinds[static_cast<size_t>(i)]) {
    case MH_UNKNOWN_SECOND_ORDER:
      return e.run.xdd[i];
    case MH_UNKNOWN_FIRST_ORDER:
      return e.run.xd[i];
    default:
      return e.run.x[i];
  }
}

std::string unknown_unit(const Simulation::Engine& e, int i) {
  if (i >= e.n_m) return e.states.state_info[static_cast<size_t>(i - e.n_m)].unit;
  const std::string& name = e.registry.unknown_names[static_cast<size_t>(i)];
  const auto& coords = e.registry.coordinate_names;
  for (size_t j = 0; j < coords.size(); ++j)
    if (coords[j] == name) return e.registry.coordinate_is_angle[j] != 0 ? "rad" : "m";
  return "";
}

std::string unknown_label(const Simulation::Engine& e, int i) {
  if (i < e.n_m) return e.registry.unknown_names[static_cast<size_t>(i)];
  const VariableInfo& v = e.states.state_info[static_cast<size_t>(i - e.n_m)];
  return v.name.empty() ? v.qualified : v.name;
}

Eigen::MatrixXd constraint_tangent_space(Simulation::Engine& e) {
  if (!e.work.tangent_ws.coordinate_unknowns || e.m == 0) return {};
  e.kinematics_at(e.run.accepted.z.data(), e.run.accepted.zd.data());
  e.constraints_at_kinematics(false);
  return Eigen::MatrixXd::Identity(e.N, e.N) -
         e.cons.phi_z.completeOrthogonalDecomposition().pseudoInverse() * e.cons.phi_z;
}

ConsistentState::ConsistentState(Simulation::Engine& e, std::string who)
    : e_(e),
      who_(std::move(who)),
      r_(e.n),
      r1_(e.n),
      du_(e.n),
      row_rates_(e.n),
      start_(e.n),
      scale_(e.n),
      before_(3 * e.n_m),
      after_(3 * e.n_m) {
  const double h = e.settings.dt;
  for (int i = 0; i < e.n; ++i) {
    const uint8_t k = e.registry.kinds[static_cast<size_t>(i)];
    const double tol = e.registry.tol[i];
    scale_[i] = k == MH_UNKNOWN_SECOND_ORDER  ? tol / (h * h)
                : k == MH_UNKNOWN_FIRST_ORDER ? tol / h
                                              : tol;
  }
}

void ConsistentState::make(const char* what) {
  Simulation::Engine& e = e_;
  const double t = std::nextafter(e.run.accepted.t, HUGE_VAL);
  // The formulation's own prediction starts from its accepted state (no
  // step: h = 0 from its time), as at an explicit stage.
  e.formulation_begin_step(monohydra::step_coefficients(e.settings.dt, 0.0, 0.0, 0.0),
                           e.run.accepted.t, e.run.x, e.run.xd, e.run.xdd);
  for (int i = 0; i < e.n; ++i) {
    const uint8_t k = e.registry.kinds[static_cast<size_t>(i)];
    if (k != MH_UNKNOWN_SECOND_ORDER) e.run.xdd[i] = 0.0;
    if (k == MH_UNKNOWN_ALGEBRAIC) e.run.xd[i] = 0.0;
  }
  RateFactorization& f = e.work.rate_factor;
  if (!f.valid || f.step != e.run.accepted.step || f.scale.size() != scale_.size() ||
      f.scale != scale_)
    factor(t, what);
  solve_kept(t, 0, what);
  // The subsystems' rates again, unless the formulation's accept left its
  // unknowns, rates and accelerations as they were (no projection moved
  // them): then they are this solve's already.
  before_ << e.run.x.head(e.n_m), e.run.xd.head(e.n_m), e.run.xdd.head(e.n_m);
  accept(what);
  after_ << e.run.x.head(e.n_m), e.run.xd.head(e.n_m), e.run.xdd.head(e.n_m);
  if (e.n_s > 0 && after_ != before_) solve_kept(t, e.n_m, what);
  e.run.y = e.states.y;
  e.run.ydot = e.states.ydot;
  e.kinematics_at(e.run.accepted.z.data(), e.run.accepted.zd.data());
  e.run.reuse.invalidate();
  e.restart_integrator();
}

void ConsistentState::solve_kept(double t, int begin, const char* what) {
  Simulation::Engine& e = e_;
  RateFactorization& f = e.work.rate_factor;
  for (int i = begin; i < e.n; ++i) start_[i] = rate_unknown(e, i);
  if (solve(t, begin, begin == 0 ? f.full : f.states, what, kKeptIterations)) return;
  // The kept Jacobian is too far from this state's: factored here, and
  // solved again from the same start.
  for (int i = begin; i < e.n; ++i) rate_unknown(e, i) = start_[i];
  factor(t, what);
  if (!solve(t, begin, begin == 0 ? f.full : f.states, what, kRateIterations))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          who_ + ": the rates at the state " + what + " did not converge in " +
                              std::to_string(kRateIterations) + " iterations");
}

void ConsistentState::evaluate(double t, Eigen::VectorXd& r, const char* what) {
  if (!status_ok(e_.residual_at(t, e_.run.x, e_.run.xd, e_.run.xdd, r)) || !r.allFinite())
    throw SimulationError(
        e_.run.accepted.t, e_.run.accepted.step,
        who_ + ": the residual failed at the state " + what +
            (e_.reports.last_plugin_error.empty() ? "" : ": " + e_.reports.last_plugin_error));
}

bool ConsistentState::solve(double t, int begin, const Eigen::FullPivLU<Eigen::MatrixXd>& lu,
                            const char* what, int iterations) {
  Simulation::Engine& e = e_;
  const int count = e.n - begin;
  bool converged = false;
  double last = HUGE_VAL;  // the largest scaled increment of the iteration before
  for (int it = 0; it < iterations && !converged; ++it) {
    evaluate(t, r_, what);
    row_rates_.tail(count) = e.work.rate_factor.row_scale.tail(count).asDiagonal() * r_.tail(count);
    du_.tail(count) = -(scale_.tail(count).asDiagonal() * lu.solve(row_rates_.tail(count)));
    converged = true;
    double largest = 0.0;
    for (int i = begin; i < e.n; ++i) {
      double& u = rate_unknown(e, i);
      u += du_[i];
      largest = std::max(largest, std::abs(du_[i]) / scale_[i]);
      converged = converged && std::abs(du_[i]) <= kRateTolerance * scale_[i] + 1e-12 * std::abs(u);
    }
    // A chord iteration that contracts by less than half a step has a
    // Jacobian too far from this state's: its stopping test would stop
    // short of the solution.
    if (!converged && largest > kSlowContraction * last) return false;
    last = largest;
  }
  if (!converged) return false;
  evaluate(t, r_, what);
  return true;
}

void ConsistentState::accept(const char* what) {
  Simulation::Engine& e = e_;
  const double h = e.settings.dt;
  const mh_step_coefficients c = monohydra::step_coefficients(h, 2.0 / h, 4.0 / (h * h), 2.0 / h);
  uint32_t flags = 0;
  e.check(in_flight(*e.formulation_host, InstanceHost::Op::accept,
                    [&] {
                      const mh_unknown_buffers values =
                          monohydra::unknown_buffers(static_cast<size_t>(e.n_m), e.run.x.data(),
                                                     e.run.xd.data(), e.run.xdd.data());
                      return e.formulation.ops.accept(e.formulation.self, e.run.accepted.t, &c,
                                                      &values, &flags);
                    }),
          "formulation accept");
  if ((flags & MH_ACCEPT_REDEFINED) != 0)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          who_ + ": formulation '" + e.formulation_name +
                              "' redefined its unknowns at the state " + what +
                              " (a new partition): try a step later");
  e.check(in_flight(*e.formulation_host, InstanceHost::Op::coordinates,
                    [&] {
                      const mh_coordinate_buffers out{
                          sizeof(mh_coordinate_buffers), static_cast<uint32_t>(e.N),
                          e.run.accepted.z.data(), e.run.accepted.zd.data(),
                          e.run.accepted.zdd.data()};
                      return e.formulation.ops.coordinates(e.formulation.self, &out);
                    }),
          "formulation coordinates");
}

void ConsistentState::factor(double t, const char* what) {
  Simulation::Engine& e = e_;
  RateFactorization& f = e.work.rate_factor;
  f.valid = false;
  Eigen::MatrixXd J(e.n, e.n);
  evaluate(t, r_, what);
  for (int j = 0; j < e.n; ++j) {
    double& u = rate_unknown(e, j);
    const double saved = u, d = 1e-7 * std::max(std::abs(u), 1e3 * scale_[j]);
    u = saved + d;
    evaluate(t, r1_, what);
    u = saved;
    J.col(j) = (r1_ - r_) / d;
  }
  // Equilibrated: columns in units of the rates' scales, rows by their
  // largest entry (a volume's row in m^3/s beside a body's in N would
  // otherwise read as singular).
  J = J * scale_.asDiagonal();
  f.row_scale.resize(e.n);
  for (int i = 0; i < e.n; ++i) {
    const double big = J.row(i).lpNorm<Eigen::Infinity>();
    f.row_scale[i] = big > 0.0 ? 1.0 / big : 1.0;
  }
  J = f.row_scale.asDiagonal() * J;
  f.full.compute(J);
  // No subsystem states: no LU of an empty block (Eigen asserts on its norm).
  if (e.n_s > 0) f.states.compute(J.bottomRightCorner(e.n_s, e.n_s));
  if (!f.full.isInvertible() || (e.n_s > 0 && !f.states.isInvertible()))
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          who_ +
                              ": the rows do not determine the rates at the accepted "
                              "state (a singular mass matrix or state row?)");
  f.scale = scale_;
  f.step = e.run.accepted.step;
  f.valid = true;
}

}  // namespace mh
