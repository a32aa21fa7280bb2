// Linearisation of a running model about its current state, for control
// design: the continuous state-space matrices
//
//   dX/dt = A X + B u,   Y = C X + D u
//
// over the model's declared inputs u (its inputs:, in file order) and the
// outputs Y asked for by name. The states X are the run's own
// (state_vector.hpp): the formulation's non-algebraic Newton unknowns
// (positions x, then the velocities xd of the second-order ones) and the
// subsystems' non-algebraic states (pressures, spool positions, ...).
// Multipliers and algebraic states (a pressure source's flow) are not
// states: they follow X and u.
//
// How (linearization.cpp): central differences of the converged implicit
// step, solved with the run's analytic tangent, from states whose rates are
// made consistent first; the step's map X_{k+1} = Phi X_k + Gamma u is then
// turned into A and B by the inverse of the trapezoidal rule (Tustin):
// A = (2/h)(Phi - I)(Phi + I)^-1, exact for the trapezoidal rule on linear
// dynamics and an O(h^p) approximation for the other integrators. C and D
// are the outputs' differences at the same consistent states.
//
// Directions the formulation projects out of the state (the penalty
// formulation's coordinates across its constraints, their velocities) are
// removed by one step: their eigenvalues of A are near -2/h (h the step),
// far from any physical one; ignore them.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <string>
#include <vector>

#include "monohydra/core/simulation.hpp"
#include "monohydra/core/state_vector.hpp"

namespace mh {

struct Linearization {
  double t = 0.0;              // s: the accepted time it was taken at
  long step = 0;               // that time's step
  double h = 0.0;              // s: the step its map was taken over (the run's dt)
  Eigen::MatrixXd A, B, C, D;  // n x n, n x m, p x n, p x m
  // The step's own map, X_{k+1} = Phi X_k + Gamma u (what A and B are
  // taken from): a discrete filter's transition.
  Eigen::MatrixXd Phi, Gamma;                           // n x n, n x m
  std::vector<LinearVariable> states, inputs, outputs;  // n, m, p
};

// What a caller needs of it. A filter (extended_kalman_filter.cpp) needs
// the step's map and C alone, once every step: no input columns, and
// one-sided differences (one perturbed step per state, from the
// unperturbed one's), whose error of the order of the perturbation (the
// Newton tolerance) is far below what a filter's Jacobian must hold.
struct LinearizeOptions {
  bool inputs = true;   // B, D, Gamma (false: they have no columns)
  bool central = true;  // central differences (false: one-sided)
};

// The linearisation of `sim`'s run at its last accepted state, with the
// outputs named in `outputs`: coordinates ("z1"), their rates ("z1_dot"),
// subsystem states and outputs by their result column or qualified name
// (what mhs_find accepts, inputs aside). The run is left exactly as it was:
// its next steps are those it would have taken without the call, to the bit.
// Throws std::invalid_argument naming an unknown output, SimulationError for
// a run that has not started, one with an explicit integrator, or a step of
// the differences that failed.
Linearization linearize(Simulation& sim, const std::vector<std::string>& outputs,
                        const LinearizeOptions& options = {});

// The eigenvalues of a, slowest first (largest real part; then by imaginary part).
std::vector<std::complex<double>> eigenvalues(const Eigen::MatrixXd& a);

}  // namespace mh
