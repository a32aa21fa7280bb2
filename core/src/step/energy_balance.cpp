// The energy balance every run reports: kinetic and potential energy of the
// bodies, the work W subsystem forces do on them (trapezoidal integral of
// their power), energy stored in and dissipated by the subsystems, and the
// constraint violation. Relative to t = 0; drift = KE + PE - W.
#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"

namespace mh {

void Simulation::Engine::energy_terms(double& stored_out, double& dissipation_out,
                                      double* per_instance) {
  stored_out = 0.0;
  dissipation_out = 0.0;
  mh_subsystem_eval ev = subsystem_eval(run.accepted.t, work.eval.scratch_rows.data());
  for (size_t i = 0; i < subsystems.size(); ++i) {
    auto& s = subsystems[i];
    if (per_instance != nullptr) per_instance[i] = 0.0;
    if (s.api.ops.energy == nullptr) continue;
    point_at(ev, s);
    refresh_signals(s, ev);
    double st = 0.0, diss = 0.0;
    if (status_ok(normalized(in_flight(*s.host, InstanceHost::Op::energy, [&] {
          return s.api.ops.energy(s.api.self, &ev, &st, &diss);
        })))) {
      stored_out += st;
      dissipation_out += diss;
      if (per_instance != nullptr) per_instance[i] = diss;
    }
  }
}

// At t = 0, with the kinematics at (z0, zd0) in data and the states solved.
void Simulation::Engine::start_energy_balance() {
  reset_applied_forces(model, data);
  check(evaluate_subsystems(run.accepted.t, work.eval.scratch_rows.data()), "subsystem evaluation");
  run.energy.power_k = work.eval.power;
  if (formulation.ops.write_outputs != nullptr)
    check(in_flight(*formulation_host, InstanceHost::Op::write_outputs,
                    [&] {
                      return formulation.ops.write_outputs(
                          formulation.self, registry.outputs.data(), static_cast<uint32_t>(n_o));
                    }),
          "formulation write_outputs");
  check_outputs("at the start");
  run.outputs = registry.outputs;
  energy_terms(run.energy.stored0, run.energy.dissipation_k);
  run.energy.stored = run.energy.stored0;
  run.energy.dissipated = 0.0;
  run.energy.ke0 = mh::kinetic_energy(model, data);
  run.energy.pe0 = mh::potential_energy(model, data);
  run.energy.work = 0.0;
  measure_mechanism();
}

// After a converged step of length h: `power` is the converged iterate's.
void Simulation::Engine::update_energy_balance(double h) {
  run.energy.work +=
      0.5 * h * (run.energy.power_k + work.eval.power);  // W = integral of F . v, trapezoidal
  run.energy.power_k = work.eval.power;
  double dissipation = 0.0;
  energy_terms(run.energy.stored, dissipation);
  run.energy.dissipated += 0.5 * h * (run.energy.dissipation_k + dissipation);
  run.energy.dissipation_k = dissipation;
}

// KE, PE and |Phi| at the accepted state (kinematics in data).
void Simulation::Engine::measure_mechanism() {
  run.energy.ke = mh::kinetic_energy(model, data);
  run.energy.pe = mh::potential_energy(model, data);
  run.energy.phi_norm = 0.0;
  if (m > 0) {
    constraints_at_kinematics(false);  // usually the formulation's last evaluation, kept
    run.energy.phi_norm = cons.phi.norm();
  }
}

}  // namespace mh
