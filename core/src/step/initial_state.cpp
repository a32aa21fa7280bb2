// Consistent initial states at t = 0 (and rates after a time event): the
// algebraic states (no row involves their rate, e.g. a pressure source's
// flow) solved so that their rows vanish; optionally the states the model
// lists under equilibrium.free, solved so that the system starts at rest; and
// the rates ydot that make every state row vanish. Done once, or at a time
// event: dense forward differences are fine here.
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

// Rows of every state at the current y, ydot and the kinematics in `data`.
static void rows_at(Simulation::Engine& e, double t_eval, Eigen::VectorXd& f) {
  reset_applied_forces(e.model, e.data);
  const mh_status st = e.evaluate_subsystems(t_eval, f.data());
  e.check(st, "subsystem evaluation");
}

// d rows / d ydot by forward differences into J (n_s x n_s), with the
// entries that are round-off (below 1e-9 of their row's largest) set to zero:
// a state is algebraic when no row involves its rate. f0, f1: n_s each.
static void rate_jacobian(Simulation::Engine& e, double t_eval, Eigen::VectorXd& f0,
                          Eigen::VectorXd& f1, Eigen::MatrixXd& J) {
  rows_at(e, t_eval, f0);
  for (int c = 0; c < e.n_s; ++c) {
    // Large enough to show against a row's other terms (a volume's C pdot
    // beside a flow 1e9 times larger): scaled by the state itself.
    const double h = 1e-6 * std::max({1.0, std::abs(e.ydot[c]), std::abs(e.y[c])});
    e.ydot[c] += h;
    rows_at(e, t_eval, f1);
    e.ydot[c] -= h;
    J.col(c) = (f1 - f0) / h;
  }
  for (int r = 0; r < e.n_s; ++r) {
    const double big = J.row(r).lpNorm<Eigen::Infinity>();
    for (int c = 0; c < e.n_s; ++c)
      if (std::abs(J(r, c)) <= 1e-9 * big) J(r, c) = 0.0;
  }
}

// Which states are algebraic (no row involves their rate, e.g. a pressure
// source's flow): the integrator gives them no rate. Structural, so decided
// once, at the initial configuration.
void Simulation::Engine::classify_states() {
  algebraic.assign(static_cast<size_t>(n_s), 0);
  rate_states.clear();
  rate_rows.clear();
  if (n_s == 0) return;
  forward_kinematics(model, data, z0, zd0);
  ydot.setZero(n_s);
  rates_ws.f0.setZero(n_s);
  rates_ws.f1.setZero(n_s);
  rates_ws.J.setZero(n_s, n_s);
  rate_jacobian(*this, 0.0, rates_ws.f0, rates_ws.f1, rates_ws.J);
  const Eigen::MatrixXd& J = rates_ws.J;
  for (int c = 0; c < n_s; ++c) {
    if (J.col(c).lpNorm<Eigen::Infinity>() == 0.0)
      algebraic[static_cast<size_t>(c)] = 1;
    else
      rate_states.push_back(c);
  }
  for (int r0 = 0; r0 < n_s; ++r0)
    if (J.row(r0).lpNorm<Eigen::Infinity>() > 0.0) rate_rows.push_back(r0);
  if (rate_states.size() != rate_rows.size())
    fail("the state rates cannot be found: " + std::to_string(rate_rows.size()) +
         " subsystem rows involve rates, but " + std::to_string(rate_states.size()) +
         " states have rates that rows involve");
  // solve_initial_rates' work, sized once: it runs at time events too,
  // inside the time step.
  const Eigen::Index k = static_cast<Eigen::Index>(rate_states.size());
  rates_ws.Jr.setZero(k, k);
  rates_ws.fr.setZero(k);
  rates_ws.dr.setZero(k);
  rates_ws.step.setZero(n_s);
  rates_ws.lu = Eigen::FullPivLU<Eigen::MatrixXd>(k, k);
}

// ydot: the state rows are F(ydot, y) = 0 at the current kinematics; Newton
// with a forward-difference Jacobian, over the rates and rows the structure
// found at t0 (classify_states): which rows involve rates does not change
// during a run, and deciding it anew from differences at every time event
// would let round-off move a state between the classes.
void Simulation::Engine::solve_initial_rates(double t_eval) {
  if (n_s == 0) return;
  const int k = static_cast<int>(rate_states.size());
  if (k == 0) return;  // every state is algebraic: no rate to find (and no 0 x 0 LU)
  // In the workspace classify_states() sized: no allocation at a time event.
  RatesWorkspace& w = rates_ws;
  for (int it = 0; it < 20; ++it) {
    rate_jacobian(*this, t_eval, w.f0, w.f1, w.J);
    rows_at(*this, t_eval, w.f0);
    for (int a = 0; a < k; ++a) {
      w.fr[a] = w.f0[rate_rows[static_cast<size_t>(a)]];
      for (int b = 0; b < k; ++b)
        w.Jr(a, b) = w.J(rate_rows[static_cast<size_t>(a)], rate_states[static_cast<size_t>(b)]);
    }
    w.lu.compute(w.Jr);
    if (!w.lu.isInvertible())
      fail(
          "the state rates cannot be found: the subsystem rows do not determine every state's "
          "rate (is each state's own term missing?)");
    // dr = Jr^-1 (-fr), as FullPivLU::solve computes it (Jr = P^-1 L U Q^-1),
    // in place: solve() would allocate its intermediate vector.
    w.fr = -w.fr;
    w.dr.noalias() = w.lu.permutationP() * w.fr;
    w.lu.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(w.dr);
    w.lu.matrixLU().triangularView<Eigen::Upper>().solveInPlace(w.dr);
    w.fr.noalias() = w.lu.permutationQ() * w.dr;
    w.step.setZero();
    for (int b = 0; b < k; ++b) w.step[rate_states[static_cast<size_t>(b)]] = w.fr[b];
    ydot += w.step;
    if (w.step.norm() <= 1e-12 * (1.0 + ydot.norm())) break;
  }
}

// Gauss-Newton on the unknown states u (algebraic ones, and equilibrium.free)
// for: the algebraic rows (always); with equilibrium, every state row at
// ydot = 0 and the static balance R^T Q'(z0, 0, y) = 0, R spanning the null
// space of Phi_z (so that Q' is held by constraint reactions: zdd = 0).
void Simulation::Engine::solve_algebraic_and_equilibrium() {
  if (n_s == 0) return;
  const double t0 = 0.0;
  const bool equilibrium = !file->equilibrium_free.empty();
  std::vector<int> unknowns;
  std::vector<char> is_unknown(static_cast<size_t>(n_s), 0);
  for (size_t i = 0; i < file->equilibrium_free.size(); ++i) {
    const std::string& name = file->equilibrium_free[i];
    int found = -1;
    for (int k = 0; k < n_s; ++k)
      if (state_info[static_cast<size_t>(k)].name == name ||
          state_info[static_cast<size_t>(k)].qualified == name)
        found = k;
    if (found < 0) {
      std::string known;
      for (const VariableInfo& v : state_info) {
        const std::string& column = v.name;
        const std::string& q = v.qualified;
        known += (known.empty() ? "" : ", ") +
                 (column.empty() || column == q ? q : column + " (" + q + ")");
      }
      throw InputError(file->equilibrium_marks[i], "equilibrium.free",
                       "unknown state '" + name +
                           "' (expected a state's result column or 'instance.state' name: " +
                           (known.empty() ? std::string("the model has no states") : known) + ")");
    }
    if (is_unknown[static_cast<size_t>(found)] == 0) unknowns.push_back(found);
    is_unknown[static_cast<size_t>(found)] = 1;
  }
  if (equilibrium && zd0.lpNorm<Eigen::Infinity>() > 0.0)
    fail("equilibrium: the mechanism must start at rest (its initial rates are not zero)");

  // Algebraic states and rows, at the rates the state starts with (zero).
  forward_kinematics(model, data, z0, zd0);
  rate_jacobian(*this, t0, rates_ws.f0, rates_ws.f1, rates_ws.J);
  const Eigen::MatrixXd Jd = rates_ws.J;
  std::vector<int> rows;
  for (int c = 0; c < n_s; ++c)
    if (Jd.col(c).lpNorm<Eigen::Infinity>() == 0.0 && is_unknown[static_cast<size_t>(c)] == 0) {
      unknowns.push_back(c);
      is_unknown[static_cast<size_t>(c)] = 1;
    }
  for (int r0 = 0; r0 < n_s; ++r0)
    if (equilibrium || Jd.row(r0).lpNorm<Eigen::Infinity>() == 0.0) rows.push_back(r0);
  if (unknowns.empty()) return;

  // The static balance's directions: the null space of Phi_z at z0.
  Eigen::MatrixXd R;
  if (equilibrium) {
    if (m > 0) {
      evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
      constraints_valid = false;  // at kinematics of its own, not kept
      R = Eigen::FullPivLU<Eigen::MatrixXd>(phi_z).kernel();
    } else {
      R = Eigen::MatrixXd::Identity(N, N);
    }
  }
  const Eigen::VectorXd zero_rates = Eigen::VectorXd::Zero(N);
  const int n_rows = static_cast<int>(rows.size()) + (equilibrium ? static_cast<int>(R.cols()) : 0);
  const int k = static_cast<int>(unknowns.size());
  Eigen::VectorXd f(n_s);
  const auto equations = [&](Eigen::VectorXd& out) {
    if (equilibrium) {
      const mh_status st = evaluate_mechanics(MH_EVAL_DYNAMICS, t0, z0.data(), zero_rates.data());
      check(st, "equilibrium: subsystem evaluation");
      std::copy(scratch_rows.data(), scratch_rows.data() + n_s, f.data());
      out.tail(R.cols()) = R.transpose() * data.Q;
    } else {
      rows_at(*this, t0, f);
    }
    for (size_t i = 0; i < rows.size(); ++i) out[static_cast<Eigen::Index>(i)] = f[rows[i]];
  };
  const Eigen::VectorXd saved_ydot = ydot;
  if (equilibrium) ydot.setZero();
  Eigen::VectorXd F(n_rows), F1(n_rows);
  Eigen::MatrixXd J(n_rows, k);
  Eigen::VectorXd scale(n_rows);
  double worst = 0.0;
  for (int it = 0; it < 50; ++it) {
    equations(F);
    for (int j = 0; j < k; ++j) {
      const int c = unknowns[static_cast<size_t>(j)];
      const double h = 1e-7 * std::max(std::abs(y[c]), 1e3 * state_tol[c]);
      y[c] += h;
      equations(F1);
      y[c] -= h;
      J.col(j) = (F1 - F) / h;
    }
    // Rows in units of the unknowns' tolerances.
    for (int i = 0; i < n_rows; ++i) {
      double s = 0.0;
      for (int j = 0; j < k; ++j)
        s += std::abs(J(i, j)) * state_tol[unknowns[static_cast<size_t>(j)]];
      scale[i] = s > 0.0 ? 1.0 / s : 0.0;
    }
    const Eigen::MatrixXd Js = scale.asDiagonal() * J;
    const Eigen::VectorXd du =
        Js.completeOrthogonalDecomposition().solve(-(scale.asDiagonal() * F));
    worst = 0.0;
    for (int j = 0; j < k; ++j) {
      const int c = unknowns[static_cast<size_t>(j)];
      y[c] += du[j];
      worst = std::max(worst, std::abs(du[j]) / state_tol[c]);
    }
    if (worst <= 1e-3) break;
  }
  equations(F);
  if (!(worst <= 1.0))
    fail("the initial states could not be solved (the last correction was " + short_number(worst) +
         " times the tolerance)");
  // Every equation must hold: a row that the unknowns cannot move must be zero.
  for (int i = 0; i < n_rows; ++i) {
    const bool ok = scale[i] > 0.0 ? std::abs(F[i]) * scale[i] <= 10.0 : std::abs(F[i]) <= 1e-9;
    if (ok) continue;
    const std::string what =
        i < static_cast<int>(rows.size())
            ? "the row of state '" +
                  state_info[static_cast<size_t>(rows[static_cast<size_t>(i)])].name +
                  "' stays at " + short_number(F[i])
            : "the mechanism is not held: its static balance stays at " + short_number(F[i]) +
                  " N or N m";
    fail(std::string(equilibrium ? "no equilibrium with the states under equilibrium.free"
                                 : "the algebraic states cannot be solved") +
         ": " + what);
  }
  if (equilibrium)
    ydot.setZero();
  else
    ydot = saved_ydot;
}

}  // namespace mh
