// The one Newton iteration of the engine, used by every nonlinear system a
// run solves: the time step over every unknown (Eq. 37), the rates at an
// explicit stage, the initial rates, the initial algebraic states and
// equilibrium, the closing of the loops. In the manner of SUNDIALS'
// SUNNonlinearSolver: the problem evaluates its residual, sets up and solves
// its linear model and measures an increment in its unknowns' tolerances;
// the iteration, the order of those calls and their outcome are here, once.
// A problem's own failures (a plugin's error, a singular tangent) are thrown
// from its calls; the iteration reports only how it ended.
#pragma once

#include <Eigen/Core>

namespace mh {

class NewtonProblem {
 public:
  virtual ~NewtonProblem() = default;
  // F at the current iterate into `f`.
  virtual void residual(Eigen::VectorXd& f) = 0;
  // Before an iteration: must the linear model be set up anew? (Always,
  // unless the problem keeps a factorization: modified Newton.)
  virtual bool needs_setup() { return true; }
  // The linear model at the current iterate: J assembled and factored.
  virtual void setup() = 0;
  // The Newton increment: du solving J du = -f (in the least-squares sense
  // where J is not square).
  virtual void solve(const Eigen::VectorXd& f, Eigen::VectorXd& du) = 0;
  // The iterate moves by `du`.
  virtual void add(const Eigen::VectorXd& du) = 0;
  // Undoes add(du): the iterate as it was before.
  virtual void subtract(const Eigen::VectorXd& du) = 0;
  // The increment's size in the unknowns' tolerances, measured after add (a
  // relative part may read the new iterate); `worst`: its largest entry.
  virtual double measure(const Eigen::VectorXd& du, int& worst) = 0;
  // After measure: false when the increment must be undone and the iteration
  // repeated from the iterate before it (a kept factorization that diverges).
  virtual bool keep(double /*size*/) { return true; }
  // After a kept increment, before the residual at the new iterate. True
  // when it changed what the residual depends on (a formulation's
  // iteration_done): a damped iteration, which evaluated the residual to test
  // the increment, evaluates it again.
  virtual bool accepted() { return false; }
  // After the residual of an iteration: converged with an increment of
  // `size`? (Within tolerance, by default.)
  virtual bool converged(double size) { return size <= 1.0; }
  // Whether a residual solves the problem as it stands, before any increment
  // (a problem whose test is on F itself rather than on the increment).
  virtual bool solved(const Eigen::VectorXd& /*f*/) { return false; }
  // After an unconverged iteration `iteration`: stop and accept the iterate?
  virtual bool stop_early(int /*iteration*/) { return false; }
};

struct NewtonOutcome {
  enum class End {
    converged,      // measured within tolerance (or solved by its residual)
    stopped,        // stop_early accepted the iterate unconverged
    not_finite,     // the residual has a non-finite entry: `row`
    not_converged,  // max_iterations without convergence
    no_descent      // damped: no step along the increment passed the monotonicity test
  };
  End end = End::not_converged;
  int iterations = 0;            // increments made (undone ones included)
  double size = 0.0;             // the last increment's measure
  int worst = 0;                 // its largest entry
  int row = 0;                   // the first non-finite row (End::not_finite)
  int damped = 0;                // increments shortened by the line search
  double smallest_factor = 1.0;  // the shortest fraction of an increment taken
};

// Damped Newton, the globalization of solver.line_search: each increment du
// is taken as lambda du with lambda = 1, 1/2, 1/4, ... until the natural
// monotonicity test holds (Deuflhard's, as NLEQ applies it): the simplified
// increment at the trial point, dbar = -J^-1 F(u + lambda du) with the same
// factorization, no larger than (1 - lambda / 4) du, both measured in the
// unknowns' tolerances. Measured in the unknowns, the test needs no scaling
// of rows that mix newtons, pascals and cubic metres per second, as a
// residual norm would. It costs one more linear solve per iteration and a
// residual per halving. `trial` and `correction` are sized to the unknowns.
struct NewtonDamping {
  Eigen::VectorXd& trial;
  Eigen::VectorXd& correction;
  int max_halvings = 10;  // lambda down to 2^-10, then End::no_descent
};

// Newton from the problem's current iterate, with `f` and `du` as its
// workspaces (sized to the rows and to the unknowns: nothing is allocated).
NewtonOutcome newton_iterate(NewtonProblem& problem, int max_iterations, Eigen::VectorXd& f,
                             Eigen::VectorXd& du, NewtonDamping* damping = nullptr);

}  // namespace mh
