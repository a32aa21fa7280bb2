// The state of a run between two steps as one value that can be copied: what
// the host keeps (time, step, unknowns, subsystem states, outputs, the energy
// balance, the counters) and every plugin instance's own bytes (state.h). A
// run restored from it goes on exactly as the run it was saved from went on:
// the same steps to the last bit, and the same work counted: what snapshots,
// a controller's branches and an FMU's get and set state stand on.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/explicit_stability.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/core/tangent_reuse.hpp"

namespace mh {

// A snapshot that cannot be taken or put back: names why (the instance that
// keeps state it cannot save, the run a snapshot is not of).
class RunStateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The energy balance's sums, all relative to t = 0 (Simulation::drift).
struct EnergyBalance {
  double ke0 = 0.0, pe0 = 0.0, ke = 0.0, pe = 0.0;
  double work = 0.0, power_k = 0.0;
  double stored0 = 0.0, stored = 0.0, dissipated = 0.0, dissipation_k = 0.0;
  double phi_norm = 0.0;
};

// The last accepted point of the run, and the step being attempted.
struct AcceptedPoint {
  double t = 0.0;
  long step = 0;
  double attempt_t = 0.0;
  long attempt_step = 0;
  Eigen::VectorXd z, zd, zdd;
  bool started = false;
};

// Everything the host keeps of a run that changes from step to step (the
// plugin instances keep theirs, state.h): the one value the step reads and
// writes. A snapshot is a copy of it, restore assigns it back, and its bytes
// are one walk of its fields (run_state_bytes.cpp); the rest of the engine is
// fixed by the model or recomputed from this (kinematics, tangents, the
// integrator's map, the caches of the constraints and the rates' factors).
struct RunData {
  AcceptedPoint accepted;
  EnergyBalance energy;
  // Newton's unknowns and their rates: the iterate within a step, the
  // accepted values between steps.
  Eigen::VectorXd x, xd, xdd;
  Eigen::VectorXd y, ydot;  // the subsystem states and rates, accepted
  Eigen::VectorXd outputs;  // accepted
  size_t next_event = 0;    // the first time event after the accepted time
  // An explicit integrator's stability checks (explicit_stability.cpp).
  bool stability_due = false;
  long stability_next_step = 0;
  double stability_worst_excess = 0.0;
  ExplicitStability stability;
  Simulation::WorkCounters counters;  // since start()
  StepStats last_step;
  // Where the host's constraint cache stands (Phi at constraint_z, its rates
  // at constraint_zd), so that a restored run's passes, as the counters count
  // them, are the saved run's.
  Eigen::VectorXd constraint_z, constraint_zd;
  bool constraint_positions_valid = false, constraint_rates_valid = false;
  // What the Newton loops keep from step to step: full, per-step or modified
  // Newton and its factorization's age (the factors themselves are
  // RunState::kept_tangent's); an explicit integrator's rates Jacobian.
  TangentReuse reuse;
  bool rates_jacobian_valid = false;
  Eigen::MatrixXd rates_jacobian;
  // The model's inputs: their values, which still follow their tables, and
  // whether a change waits for the next step (Simulation::set_input).
  std::vector<double> input_values;
  std::vector<uint8_t> input_follows_table;
  bool input_jump_pending = false;
};

struct RunState {
  // The run it is of (formulation, integrator, dt, every coordinate's, state's
  // and output's name): restore refuses another.
  std::string run_key;
  RunData data;
  // Modified Newton's factorization, as the tangent's values it was made
  // from (refactored on restore: the same factors); empty: none kept.
  std::vector<double> kept_tangent;
  // The values of the model a run changes in place when it was saved (each
  // body's mass, centre of mass and inertia, then gravity: model_values_of):
  // Simulation::model_differences names those a run has otherwise.
  std::vector<double> model_values;
  // The instances' own states (state.h), one after the other in the run's
  // order (formulation, integrator, subsystems), and each one's length.
  std::vector<uint64_t> part_sizes;
  std::vector<unsigned char> part_bytes;
};

}  // namespace mh
