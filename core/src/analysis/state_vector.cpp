// The run's state as one vector, read and set between steps
// (state_vector.hpp).
#include "monohydra/core/state_vector.hpp"

#include <cmath>
#include <stdexcept>

#include "engine.hpp"
#include "monohydra/core/run_state.hpp"
#include "state_slots.hpp"

namespace mh {

namespace {

const Simulation::Engine& started(const Simulation::Engine* e, const char* what) {
  if (!e->run.accepted.started)
    throw SimulationError(e->run.accepted.t, e->run.accepted.step,
                          std::string(what) + ": the run has not started (call start() first)");
  return *e;
}

}  // namespace

std::vector<LinearVariable> state_variables(const Simulation& sim) {
  const Simulation::Engine& e = started(sim.engine_.get(), "state_variables");
  std::vector<LinearVariable> out;
  for (const StateSlot& s : state_slots(e)) {
    const std::string unit = unknown_unit(e, s.unknown);
    out.push_back({unknown_label(e, s.unknown) + (s.rate ? "_dot" : ""),
                   s.rate ? (unit.empty() ? "1/s" : unit + "/s") : unit});
  }
  return out;
}

Eigen::VectorXd state_values(const Simulation& sim) {
  const Simulation::Engine& e = started(sim.engine_.get(), "state_values");
  const std::vector<StateSlot> slots = state_slots(e);
  Eigen::VectorXd out(static_cast<Eigen::Index>(slots.size()));
  for (size_t k = 0; k < slots.size(); ++k)
    out[static_cast<Eigen::Index>(k)] =
        slots[k].rate ? e.run.xd[slots[k].unknown] : e.run.x[slots[k].unknown];
  return out;
}

void set_state_values(Simulation& sim, const Eigen::VectorXd& values) {
  Simulation::Engine& e = *sim.engine_;
  started(&e, "set_state_values");
  if (e.explicit_method)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "set_state_values: the run's integrator '" + e.integrator_name +
                              "' is explicit (a state is made consistent through an implicit "
                              "step's residual)");
  if (e.sens.active)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "set_state_values: the run tracks forward sensitivities, whose columns "
                          "belong to the state it reached");
  const std::vector<StateSlot> slots = state_slots(e);
  if (values.size() != static_cast<Eigen::Index>(slots.size()))
    throw std::invalid_argument("set_state_values: " + std::to_string(values.size()) +
                                " values for a state of " + std::to_string(slots.size()));
  const std::vector<LinearVariable> names = state_variables(sim);
  for (Eigen::Index k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      throw std::invalid_argument("set_state_values: " + names[static_cast<size_t>(k)].name +
                                  " is not a finite number");
  const RunState saved = sim.save_state();
  try {
    // Penalty's coordinates moved within the constraints' tangent space.
    const Eigen::MatrixXd tangent_space = constraint_tangent_space(e);
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(e.n), dxd = Eigen::VectorXd::Zero(e.n);
    for (size_t k = 0; k < slots.size(); ++k) {
      const StateSlot& s = slots[k];
      const double change = values[static_cast<Eigen::Index>(k)] - slot_value(e, s);
      (s.rate ? dxd : dx)[s.unknown] = change;
    }
    if (tangent_space.size() > 0) {
      dx.head(e.N) = tangent_space * dx.head(e.N);
      dxd.head(e.N) = tangent_space * dxd.head(e.N);
    }
    e.run.x += dx;
    e.run.xd += dxd;
    ConsistentState consistent(e, "set_state_values");
    consistent.make("set from outside");
    if (e.formulation.ops.write_outputs != nullptr)
      e.check(in_flight(*e.formulation_host, InstanceHost::Op::write_outputs,
                        [&] {
                          return e.formulation.ops.write_outputs(e.formulation.self,
                                                                 e.registry.outputs.data(),
                                                                 static_cast<uint32_t>(e.n_o));
                        }),
              "formulation write_outputs");
    e.run.outputs = e.registry.outputs;
    e.measure_mechanism();  // KE, PE and |Phi| of the result rows, at the new state
  } catch (...) {
    sim.restore_state(saved);
    throw;
  }
}

}  // namespace mh
