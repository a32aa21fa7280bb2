// Snapshots of a run between two steps (run_state.hpp): the host's part
// copied, each plugin instance's part through its MH_EXT_STATE (state.h).
// Everything else the engine holds is either fixed by the model (sizes,
// patterns, names) or recomputed by the next step from what is saved here
// (kinematics, tangents, the integrator's map), so it is not state.
#include <algorithm>
#include <cstring>

#include "engine.hpp"
#include "plugins/abi_struct.hpp"

namespace mh {

namespace {

// Per body: mass, centre of mass (3), inertia (3 x 3, column-major).
constexpr size_t kModelValuesPerBody = 13;

// The values a run changes in place (RunState::model_values), then gravity.
void model_values_of(const Model& model, std::vector<double>& out) {
  out.resize(model.bodies.size() * kModelValuesPerBody + 3);
  size_t at = 0;
  for (const Body& b : model.bodies) {
    out[at++] = b.mass;
    for (int i = 0; i < 3; ++i) out[at++] = b.com_B[i];
    for (int i = 0; i < 9; ++i) out[at++] = b.inertia_B(i % 3, i / 3);
  }
  for (int i = 0; i < 3; ++i) out[at++] = model.gravity[i];
}

// The instance's MH_EXT_STATE, read as this host's struct (abi_struct.hpp).
template <class Table>
mh_state_extension state_extension_of(const Table* self, const Table& ops, InstanceHost& host) {
  if (ops.get_extension == nullptr) return {};
  const void* ext = in_flight(host, InstanceHost::Op::get_extension,
                              [&] { return ops.get_extension(self, MH_EXT_STATE); });
  return read_struct(static_cast<const mh_state_extension*>(ext));
}

}  // namespace

void Simulation::Engine::find_state_parts() {
  if (work.snapshot.found) return;
  work.snapshot.parts.clear();
  const auto add = [&](const void* self, mh_state_extension ext, InstanceHost& host,
                       bool keeps_state) {
    StatePart part;
    part.self = self;
    part.host = &host;
    part.keeps_state = keeps_state;
    const bool complete = ext.size != nullptr && ext.save != nullptr && ext.load != nullptr;
    if (complete) {
      part.ext = ext;
      part.size = in_flight(host, InstanceHost::Op::get_extension, [&] { return ext.size(self); });
    }
    if (!complete && !keeps_state) return;  // nothing of its own
    work.snapshot.parts.push_back(part);
  };
  add(formulation.self, state_extension_of(formulation.self, formulation.ops, *formulation_host),
      *formulation_host, true);
  add(integrator.self, state_extension_of(integrator.self, integrator.ops, *integrator_host),
      *integrator_host, true);
  for (SubsystemInstance& s : subsystems)
    add(s.api.self, state_extension_of(s.api.self, s.api.ops, *s.host), *s.host,
        s.api.ops.accept != nullptr);
  work.snapshot.key = run_key();
  work.snapshot.found = true;
}

// What makes a state of this run one of another: the plugins, the step, the
// Newton variant and the names of everything the state holds.
std::string Simulation::Engine::run_key() const {
  // Full and per-step Newton keep no factorization from step to step: a state
  // of one restores into the other.
  std::string key = formulation_name + '|' + integrator_name + '|' + short_number(settings.dt) +
                    (settings.newton == NewtonKind::modified ? "|modified" : "|full");
  for (const auto& name : registry.coordinate_names) key += '|' + name;
  for (const auto& name : registry.unknown_names) key += '|' + name;
  for (const auto& v : states.state_info) key += '|' + v.qualified;
  for (const auto& v : registry.output_info) key += '|' + v.qualified;
  for (const InputSignal& in : signals.inputs) key += "|input " + in.spec->name;
  return key;
}

void Simulation::Engine::save_state(RunState& into) {
  if (!run.accepted.started)
    throw RunStateError(
        "a run's state is saved between steps, after start(): this run has not "
        "started");
  find_state_parts();
  uint64_t total = 0;
  for (const StatePart& part : work.snapshot.parts) {
    if (part.ext.save == nullptr)
      throw RunStateError(part.host->label +
                          " keeps state between steps and cannot save it (it offers no " +
                          MH_EXT_STATE + " extension, docs/sdk.md): this run cannot be saved");
    total += part.size;
  }
  into.run_key = work.snapshot.key;
  into.data = run;
  if (run.reuse.keeps_factorization())
    into.kept_tangent.assign(work.tangent_ws.values.begin(), work.tangent_ws.values.end());
  else
    into.kept_tangent.clear();
  model_values_of(model, into.model_values);
  into.part_sizes.resize(work.snapshot.parts.size());
  into.part_bytes.resize(static_cast<size_t>(total));
  size_t at = 0;
  for (size_t k = 0; k < work.snapshot.parts.size(); ++k) {
    const StatePart& part = work.snapshot.parts[k];
    into.part_sizes[k] = part.size;
    reports.last_plugin_error.clear();
    const mh_status st = in_flight(*part.host, InstanceHost::Op::save_state, [&] {
      return part.ext.save(part.self, into.part_bytes.data() + at, part.size);
    });
    if (!status_ok(normalized(st)))
      throw RunStateError(status_reason(st, part.host->label + " save_state"));
    at += static_cast<size_t>(part.size);
  }
}

void Simulation::Engine::restore_state(const RunState& from) {
  find_state_parts();
  if (from.run_key != work.snapshot.key)
    throw RunStateError(
        "the state is not one of this run: it was saved from another model, formulation, "
        "integrator or step (formulation '" +
        from.run_key.substr(0, from.run_key.find('|')) + "', this run's '" + formulation_name +
        "')");
  bool sizes_match = from.part_sizes.size() == work.snapshot.parts.size();
  uint64_t total = 0;
  for (size_t k = 0; sizes_match && k < work.snapshot.parts.size(); ++k) {
    sizes_match = from.part_sizes[k] == work.snapshot.parts[k].size;
    total += from.part_sizes[k];
  }
  if (!sizes_match || total != from.part_bytes.size())
    throw RunStateError(
        "the state's plugin parts are not this run's (another build of a plugin, or bytes "
        "changed): it cannot be restored");
  for (const StatePart& part : work.snapshot.parts)
    if (part.ext.load == nullptr)
      throw RunStateError(part.host->label +
                          " keeps state between steps and cannot load it (it offers no " +
                          MH_EXT_STATE + " extension, docs/sdk.md): no state can be restored");
  // A run restored before it started: start() sizes what the steps use; the
  // state then overwrites what start computed.
  if (!run.accepted.started) start();
  // A state read from bytes (run_state_bytes.hpp) has the right key but its
  // lengths come from the bytes: each is this run's, or nothing is restored.
  const auto sized = [](const Eigen::VectorXd& v, Eigen::Index len) { return v.size() == len; };
  const RunData& d = from.data;
  const Eigen::Index nz = run.accepted.z.size(), nx = run.x.size();
  const bool lengths_match =
      d.accepted.started && sized(d.accepted.z, nz) && sized(d.accepted.zd, nz) &&
      sized(d.accepted.zdd, nz) && sized(d.x, nx) && sized(d.xd, nx) && sized(d.xdd, nx) &&
      sized(d.y, run.y.size()) && sized(d.ydot, run.ydot.size()) &&
      sized(d.outputs, run.outputs.size()) && d.next_event <= states.time_events.size() &&
      (!d.constraint_positions_valid || sized(d.constraint_z, nz)) &&
      (!d.constraint_rates_valid || sized(d.constraint_zd, nz)) &&
      (!d.rates_jacobian_valid ||
       (d.rates_jacobian.rows() == nx && d.rates_jacobian.cols() == nx)) &&
      d.input_values.size() == signals.inputs.size() &&
      d.input_follows_table.size() == signals.inputs.size();
  if (!lengths_match)
    throw RunStateError(
        "the state's lengths are not this run's (its bytes were changed): it cannot be restored");
  // All parts or none: should one instance refuse its bytes, those loaded
  // before it take back what they had.
  RunState& before = work.snapshot.before;
  save_state(before);
  size_t at = 0;
  for (size_t k = 0; k < work.snapshot.parts.size(); ++k) {
    const StatePart& part = work.snapshot.parts[k];
    reports.last_plugin_error.clear();
    const mh_status st = in_flight(*part.host, InstanceHost::Op::load_state, [&] {
      return part.ext.load(part.self, from.part_bytes.data() + at, part.size);
    });
    if (!status_ok(normalized(st))) {
      const std::string reason = status_reason(st, part.host->label + " load_state");
      size_t back = 0;
      for (size_t j = 0; j < k; ++j) {
        const StatePart& done = work.snapshot.parts[j];
        (void)in_flight(*done.host, InstanceHost::Op::load_state, [&] {
          return done.ext.load(done.self, before.part_bytes.data() + back, done.size);
        });
        back += static_cast<size_t>(done.size);
      }
      throw RunStateError(reason + "; the run is as it was");
    }
    at += static_cast<size_t>(part.size);
  }
  run = from.data;
  // The iterate's copies as the accepted state (the next step starts there).
  states.y = run.y;
  states.ydot = run.ydot;
  registry.outputs = run.outputs;
  if (run.rates_jacobian_valid)
    work.stages.rates_lu.compute(run.rates_jacobian);  // the factors the saved run kept
  // The host's caches as the saved run left them: the constraints at their
  // point, then the kinematics at the accepted state (accept_step's), and
  // the saved counters (these passes are not the run's work).
  work.eval.kinematics_valid = false;
  work.eval.iterate_evaluated = false;
  run.constraint_positions_valid = false;
  run.constraint_rates_valid = false;
  if (m > 0 && d.constraint_positions_valid) {
    kinematics_at(d.constraint_z.data(),
                  (d.constraint_rates_valid ? d.constraint_zd : d.accepted.zd).data());
    constraints_at_kinematics(d.constraint_rates_valid);
    work.eval.kinematics_valid = false;
  }
  kinematics_at(run.accepted.z.data(), run.accepted.zd.data());
  run.counters = d.counters;
  run.reuse.set_mode(reuse_mode(settings.newton));  // this run's kind, not the saved one's
  if (d.reuse.keeps_factorization()) {
    // The factors modified Newton kept, made again from the same values.
    std::vector<double>& values = work.tangent_ws.values;
    bool factored = from.kept_tangent.size() == values.size();
    if (factored) {
      std::copy(from.kept_tangent.begin(), from.kept_tangent.end(), values.begin());
      factored = work.solver.linear_solver->factor(values.data());
    }
    if (!factored) run.reuse.invalidate();  // the next step factors anew
  }
  reports.last_plugin_error.clear();
}

std::string Simulation::model_differences(const RunState& from) const {
  if (from.run_key != engine_->run_key()) return "";  // restore refuses it on its own terms
  const Model& now = engine_->model;
  std::vector<double> mine;
  model_values_of(now, mine);
  if (from.model_values.size() != mine.size())
    return "the snapshot holds " + std::to_string(from.model_values.size()) +
           " values of its model, this run's model has " + std::to_string(mine.size());
  std::string out;
  int named = 0, more = 0;
  const auto note = [&](const std::string& what, const std::string& unit, double here,
                        double there) {
    if (named == 4) {
      ++more;
      return;
    }
    ++named;
    out += (out.empty() ? "" : "; ") + what + " " + short_number(here) + " " + unit +
           " in this run, " + short_number(there) + " " + unit + " in the snapshot";
  };
  static const char* const kAxes[] = {"x", "y", "z"};
  for (size_t b = 0; b < now.bodies.size(); ++b) {
    const size_t at = b * kModelValuesPerBody;
    const std::string body = "body '" + now.bodies[b].name + "'";
    if (mine[at] != from.model_values[at])
      note(body + " mass", "kg", mine[at], from.model_values[at]);
    for (size_t i = 0; i < 3; ++i)
      if (mine[at + 1 + i] != from.model_values[at + 1 + i])
        note(body + " centre of mass " + kAxes[i], "m", mine[at + 1 + i],
             from.model_values[at + 1 + i]);
    for (size_t i = 0; i < 9; ++i)
      if (mine[at + 4 + i] != from.model_values[at + 4 + i])
        note(body + " inertia " + kAxes[i % 3] + kAxes[i / 3], "kg m^2", mine[at + 4 + i],
             from.model_values[at + 4 + i]);
  }
  const size_t g = now.bodies.size() * kModelValuesPerBody;
  for (size_t i = 0; i < 3; ++i)
    if (mine[g + i] != from.model_values[g + i])
      note(std::string("gravity ") + kAxes[i], "m/s^2", mine[g + i], from.model_values[g + i]);
  if (more > 0) out += "; and " + std::to_string(more) + " more";
  return out;
}

RunState Simulation::save_state() const {
  RunState state;
  save_state(state);
  return state;
}

void Simulation::save_state(RunState& into) const {
  engine_->save_state(into);
}

void Simulation::restore_state(const RunState& from) {
  // The sensitivities' columns and their integrators' histories are not in
  // a snapshot: restored under them, the run would go on with columns of
  // another state.
  if (engine_->sens.active)
    throw RunStateError(
        "this run tracks sensitivities, which a snapshot does not hold: restore into a run "
        "that tracks none");
  engine_->restore_state(from);
}

}  // namespace mh
