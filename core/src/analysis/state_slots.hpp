// The run's state as one vector X (linearisation, estimation): the
// formulation's positions and first-order unknowns, the velocities of its
// second-order ones, then the subsystems' non-algebraic states. What
// linearization.cpp perturbs and state_vector.cpp sets; both make the state
// consistent the same way (ConsistentState).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>
#include <vector>

#include "engine.hpp"

namespace mh {

// One component of the state vector X: unknown `unknown`'s value, or its
// rate (second-order unknowns only).
struct StateSlot {
  int unknown = 0;
  bool rate = false;
};

// The slots of X, in its order.
std::vector<StateSlot> state_slots(const Simulation::Engine& e);
double& slot_value(Simulation::Engine& e, const StateSlot& s);
// The unknown Newton solves for in row i of the consistent rates.
double& rate_unknown(Simulation::Engine& e, int i);
// The unit of unknown i: a coordinate's (the shipped formulations name their
// unknowns after the coordinates) or a subsystem state's.
std::string unknown_unit(const Simulation::Engine& e, int i);
std::string unknown_label(const Simulation::Engine& e, int i);

// A formulation whose unknowns are the coordinates (penalty,
// MH_EXT_COORDINATE_UNKNOWNS) has more of them than the mechanism's degrees
// of freedom: a coordinate moved alone leaves the constraints. The
// projector on the constraints' tangent space at the accepted z, P = I -
// Phi_z^+ Phi_z (N x N), that keeps a move on them to first order; empty
// for other formulations or a mechanism without cut joints.
Eigen::MatrixXd constraint_tangent_space(Simulation::Engine& e);

// A state of the run from the engine's x (and xd of second-order
// unknowns), as an accepted one would be: the accelerations, the
// first-order rates and the algebraic values from r = 0 at the right limit
// of the accepted time; the formulation's accept (its projections of the
// velocities and accelerations, Eqs. 20-21 for penalty, and its own record
// of the state); the subsystems' rates again at the velocities it left;
// then the integrator restarted there, as after a time event. Newton's
// Jacobian is differenced at one state and kept, by the engine, for the
// calls after it at the same step (a chord Newton: RateFactorization,
// engine.hpp), until a solve on it contracts slowly.
// `who` opens its errors ("linearize").
class ConsistentState {
 public:
  ConsistentState(Simulation::Engine& e, std::string who);

  void make(const char* what);

 private:
  void evaluate(double t, Eigen::VectorXd& r, const char* what);

  // Newton on the rate unknowns from `begin` on (0: all; n_m: the
  // subsystems'), the others held; ends with an evaluation at the solution
  // (the state's coordinates and outputs are that evaluation's). False when
  // it has not converged in `iterations` or contracts slowly.
  bool solve(double t, int begin, const Eigen::FullPivLU<Eigen::MatrixXd>& lu, const char* what,
             int iterations);
  // solve on the kept factorization; on one factored here when that fails.
  void solve_kept(double t, int begin, const char* what);

  // The formulation accepts the state (at the trapezoidal rule's weights
  // for its projections, as an explicit step hands them) and gives its
  // coordinates.
  void accept(const char* what);

  void factor(double t, const char* what);

  Simulation::Engine& e_;
  std::string who_;  // the caller, first in its errors
  Eigen::VectorXd r_, r1_, du_, row_rates_, start_, scale_;
  Eigen::VectorXd before_, after_;  // the formulation's x, xd, xdd around its accept
};

}  // namespace mh
