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
#include "solver/newton.hpp"

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
    const double h = 1e-6 * std::max({1.0, std::abs(e.states.ydot[c]), std::abs(e.states.y[c])});
    e.states.ydot[c] += h;
    rows_at(e, t_eval, f1);
    e.states.ydot[c] -= h;
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
  states.algebraic.assign(static_cast<size_t>(n_s), 0);
  states.rate_states.clear();
  states.rate_rows.clear();
  if (n_s == 0) return;
  forward_kinematics(model, data, cons.z0, cons.zd0);
  states.ydot.setZero(n_s);
  states.rates_ws.f0.setZero(n_s);
  states.rates_ws.f1.setZero(n_s);
  states.rates_ws.J.setZero(n_s, n_s);
  rate_jacobian(*this, 0.0, states.rates_ws.f0, states.rates_ws.f1, states.rates_ws.J);
  const Eigen::MatrixXd& J = states.rates_ws.J;
  for (int c = 0; c < n_s; ++c) {
    if (J.col(c).lpNorm<Eigen::Infinity>() == 0.0)
      states.algebraic[static_cast<size_t>(c)] = 1;
    else
      states.rate_states.push_back(c);
  }
  for (int r0 = 0; r0 < n_s; ++r0)
    if (J.row(r0).lpNorm<Eigen::Infinity>() > 0.0) states.rate_rows.push_back(r0);
  if (states.rate_states.size() != states.rate_rows.size())
    fail("the state rates cannot be found: " + std::to_string(states.rate_rows.size()) +
         " subsystem rows involve rates, but " + std::to_string(states.rate_states.size()) +
         " states have rates that rows involve");
  // solve_initial_rates' work, sized once: it runs at time events too,
  // inside the time step.
  const Eigen::Index k = static_cast<Eigen::Index>(states.rate_states.size());
  states.rates_ws.Jr.setZero(k, k);
  states.rates_ws.fr.setZero(k);
  states.rates_ws.dr.setZero(k);
  states.rates_ws.du.setZero(k);
  states.rates_ws.step.setZero(n_s);
  states.rates_ws.lu = Eigen::FullPivLU<Eigen::MatrixXd>(k, k);
}

namespace {

// ydot: the state rows are F(ydot, y) = 0 at the current kinematics; Newton
// with a forward-difference Jacobian, over the rates and rows the structure
// found at t0 (classify_states): which rows involve rates does not change
// during a run, and deciding it anew from differences at every time event
// would let round-off move a state between the classes. In the workspace
// classify_states() sized: no allocation at a time event.
class InitialRatesProblem final : public NewtonProblem {
 public:
  InitialRatesProblem(Simulation::Engine& e, double t_eval)
      : e_(e), w_(e.states.rates_ws), t_(t_eval) {}

  void residual(Eigen::VectorXd& f) override {
    rows_at(e_, t_, w_.f0);
    for (size_t a = 0; a < e_.states.rate_rows.size(); ++a)
      f[static_cast<Eigen::Index>(a)] = w_.f0[e_.states.rate_rows[a]];
  }
  void setup() override {
    rate_jacobian(e_, t_, w_.f0, w_.f1, w_.J);
    const size_t k = e_.states.rate_states.size();
    for (size_t a = 0; a < k; ++a)
      for (size_t b = 0; b < k; ++b)
        w_.Jr(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
            w_.J(e_.states.rate_rows[a], e_.states.rate_states[b]);
    w_.lu.compute(w_.Jr);
    if (!w_.lu.isInvertible())
      e_.fail(
          "the state rates cannot be found: the subsystem rows do not determine every state's "
          "rate (is each state's own term missing?)");
  }
  // du = Jr^-1 (-f), as FullPivLU::solve computes it (Jr = P^-1 L U Q^-1),
  // in place: solve() would allocate its intermediate vector.
  void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
    du = -f;
    w_.dr.noalias() = w_.lu.permutationP() * du;
    w_.lu.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(w_.dr);
    w_.lu.matrixLU().triangularView<Eigen::Upper>().solveInPlace(w_.dr);
    du.noalias() = w_.lu.permutationQ() * w_.dr;
  }
  void add(const Eigen::VectorXd& du) override { move(du, 1.0); }
  void subtract(const Eigen::VectorXd& du) override { move(du, -1.0); }
  // Converged when the step is round-off beside the rates.
  double measure(const Eigen::VectorXd& du, int& worst) override {
    const double norm = w_.step.norm(), bound = 1e-12 * (1.0 + e_.states.ydot.norm());
    done_ = norm <= bound;
    du.cwiseAbs().maxCoeff(&worst);
    worst = e_.states.rate_states[static_cast<size_t>(worst)];
    return norm / bound;
  }
  bool converged(double /*size*/) override { return done_; }

 private:
  void move(const Eigen::VectorXd& du, double sign) {
    w_.step.setZero();
    for (size_t b = 0; b < e_.states.rate_states.size(); ++b)
      w_.step[e_.states.rate_states[b]] = sign * du[static_cast<Eigen::Index>(b)];
    e_.states.ydot += w_.step;
  }

  Simulation::Engine& e_;
  RatesWorkspace& w_;
  double t_;
  bool done_ = false;
};

}  // namespace

void Simulation::Engine::solve_initial_rates(double t_eval) {
  if (n_s == 0) return;
  if (states.rate_states.empty())
    return;  // every state is algebraic: no rate to find (and no 0 x 0 LU)
  InitialRatesProblem problem(*this, t_eval);
  const NewtonOutcome out = newton_iterate(problem, 20, states.rates_ws.fr, states.rates_ws.du);
  // Twenty iterations that leave more than round-off keep the best rates
  // found: the step's own Newton starts from them.
  if (out.end == NewtonOutcome::End::not_finite)
    fail("the state rates cannot be found: the row of state '" +
         states.state_info[static_cast<size_t>(states.rate_rows[static_cast<size_t>(out.row)])]
             .name +
         "' is not finite");
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
      if (states.state_info[static_cast<size_t>(k)].name == name ||
          states.state_info[static_cast<size_t>(k)].qualified == name)
        found = k;
    if (found < 0) {
      std::string known;
      for (const VariableInfo& v : states.state_info) {
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
  if (equilibrium && cons.zd0.lpNorm<Eigen::Infinity>() > 0.0)
    fail("equilibrium: the mechanism must start at rest (its initial rates are not zero)");

  // Algebraic states and rows, at the rates the state starts with (zero).
  forward_kinematics(model, data, cons.z0, cons.zd0);
  rate_jacobian(*this, t0, states.rates_ws.f0, states.rates_ws.f1, states.rates_ws.J);
  const Eigen::MatrixXd Jd = states.rates_ws.J;
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
      evaluate_constraints(model, data, cons.constraints, cons.phi, cons.phi_z, cons.phi_dot_zd);
      run.constraint_positions_valid = false;  // at kinematics of its own, not kept
      R = Eigen::FullPivLU<Eigen::MatrixXd>(cons.phi_z).kernel();
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
      const mh_status st =
          evaluate_mechanics(MH_EVAL_DYNAMICS, t0, cons.z0.data(), zero_rates.data());
      check(st, "equilibrium: subsystem evaluation");
      std::copy(work.eval.scratch_rows.data(), work.eval.scratch_rows.data() + n_s, f.data());
      out.tail(R.cols()) = R.transpose() * data.Q;
    } else {
      rows_at(*this, t0, f);
    }
    for (size_t i = 0; i < rows.size(); ++i) out[static_cast<Eigen::Index>(i)] = f[rows[i]];
  };
  const Eigen::VectorXd saved_ydot = states.ydot;
  if (equilibrium) states.ydot.setZero();
  // Gauss-Newton: the Jacobian differenced, rows in units of the unknowns'
  // tolerances, the least-squares (minimum-norm) increment.
  struct AlgebraicProblem final : NewtonProblem {
    Simulation::Engine& e;
    const std::vector<int>& unknowns;
    const decltype(equations)& equations_of;
    Eigen::VectorXd F1, scale;
    Eigen::MatrixXd J;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    const Eigen::VectorXd* F = nullptr;  // the residual setup() differences from
    AlgebraicProblem(Simulation::Engine& engine, const std::vector<int>& u,
                     const decltype(equations)& eq, int n_rows)
        : e(engine),
          unknowns(u),
          equations_of(eq),
          F1(n_rows),
          scale(n_rows),
          J(n_rows, static_cast<Eigen::Index>(u.size())) {}
    double& unknown(size_t j) { return e.states.y[unknowns[j]]; }
    double tolerance(size_t j) const { return e.states.state_tol[unknowns[j]]; }
    void residual(Eigen::VectorXd& f) override {
      equations_of(f);
      F = &f;
    }
    void setup() override {
      for (size_t j = 0; j < unknowns.size(); ++j) {
        const double h = 1e-7 * std::max(std::abs(unknown(j)), 1e3 * tolerance(j));
        unknown(j) += h;
        equations_of(F1);
        unknown(j) -= h;
        J.col(static_cast<Eigen::Index>(j)) = (F1 - *F) / h;
      }
      for (Eigen::Index i = 0; i < J.rows(); ++i) {
        double sum = 0.0;
        for (size_t j = 0; j < unknowns.size(); ++j)
          sum += std::abs(J(i, static_cast<Eigen::Index>(j))) * tolerance(j);
        scale[i] = sum > 0.0 ? 1.0 / sum : 0.0;
      }
      cod.compute(scale.asDiagonal() * J);
    }
    void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) override {
      du = cod.solve(-(scale.asDiagonal() * f));
    }
    void add(const Eigen::VectorXd& du) override {
      for (size_t j = 0; j < unknowns.size(); ++j) unknown(j) += du[static_cast<Eigen::Index>(j)];
    }
    void subtract(const Eigen::VectorXd& du) override {
      for (size_t j = 0; j < unknowns.size(); ++j) unknown(j) -= du[static_cast<Eigen::Index>(j)];
    }
    double measure(const Eigen::VectorXd& du, int& worst) override {
      double size = 0.0;
      for (size_t j = 0; j < unknowns.size(); ++j) {
        const double ratio = std::abs(du[static_cast<Eigen::Index>(j)]) / tolerance(j);
        if (ratio > size) worst = unknowns[j];
        size = std::max(size, ratio);
      }
      return size;
    }
    // A thousandth of the tolerances: the rows then hold to round-off.
    bool converged(double size) override { return size <= 1e-3; }
  };
  AlgebraicProblem problem(*this, unknowns, equations, n_rows);
  Eigen::VectorXd F(n_rows), du(k);
  const NewtonOutcome out = newton_iterate(problem, 50, F, du);
  const double worst = out.size;
  const Eigen::VectorXd& scale = problem.scale;
  if (out.end == NewtonOutcome::End::not_finite)
    fail("the initial states could not be solved: an equation is not finite at the start");
  if (!(worst <= 1.0))
    fail("the initial states could not be solved (the last correction was " + short_number(worst) +
         " times the tolerance, in state '" +
         states.state_info[static_cast<size_t>(out.worst)].qualified + "')");
  // Every equation must hold: a row that the unknowns cannot move must be zero.
  for (int i = 0; i < n_rows; ++i) {
    const bool ok = scale[i] > 0.0 ? std::abs(F[i]) * scale[i] <= 10.0 : std::abs(F[i]) <= 1e-9;
    if (ok) continue;
    const std::string what =
        i < static_cast<int>(rows.size())
            ? "the row of state '" +
                  states.state_info[static_cast<size_t>(rows[static_cast<size_t>(i)])].name +
                  "' stays at " + short_number(F[i])
            : "the mechanism is not held: its static balance stays at " + short_number(F[i]) +
                  " N or N m";
    fail(std::string(equilibrium ? "no equilibrium with the states under equilibrium.free"
                                 : "the algebraic states cannot be solved") +
         ": " + what);
  }
  if (equilibrium)
    states.ydot.setZero();
  else
    states.ydot = saved_ydot;
}

}  // namespace mh
