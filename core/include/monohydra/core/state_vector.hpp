// The state of a run as one vector X, read and set from outside between
// steps: what a filter estimates and corrects (extended_kalman_filter.hpp),
// and what a linearisation's A is of (linearization.hpp). X is the
// formulation's positions and first-order unknowns, then the velocities of
// its second-order unknowns, then the subsystems' non-algebraic states
// (pressures, spool positions, ...). With double-step these are the
// independent coordinates, so any X is a state of the closed mechanism;
// multipliers, algebraic states and the accelerations follow from X.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "monohydra/core/simulation.hpp"

namespace mh {

// A state, input or output: its name (a result column's, for a state) and SI unit.
struct LinearVariable {
  std::string name;
  std::string unit;
};

// X's entries, in order: "z1", "z1_dot", "p1", ... (the unknowns' names, a
// rate with _dot). Throws SimulationError before start().
std::vector<LinearVariable> state_variables(const Simulation& sim);
// X at the last accepted step.
Eigen::VectorXd state_values(const Simulation& sim);

// Puts X in place of the accepted state, at the same time and step, made
// consistent as a state the run could have reached: the accelerations,
// first-order rates and algebraic unknowns solved from the residual = 0,
// the formulation's accept (penalty's projections of the velocities and
// accelerations, Eqs. 20-21), the integrator restarted there as after a
// time event. A formulation whose unknowns are all the coordinates
// (penalty) has its change of positions and velocities projected on the
// constraints' tangent space at the accepted coordinates, so that the
// constraints stay satisfied to first order in the change. Throws
// std::invalid_argument for a vector of another size or a non-finite entry
// (naming it), SimulationError for a run not started, one with an explicit
// integrator or forward sensitivities, or rates that do not converge at
// the new state; a throw leaves the run as it was.
void set_state_values(Simulation& sim, const Eigen::VectorXd& values);

}  // namespace mh
