// The mh_host table the core hands to every plugin instance: options from the
// model file, logging, state and point registration, and the semirecursive
// kinematics and dynamics. No exception crosses the C boundary.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <unordered_set>

#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/inverse_dynamics.h"
#include "monohydra/model_folder.h"
#include "monohydra/sparsity.h"
#include "monohydra/visual.h"
#include "plugins/abi_struct.hpp"
#include "plugins/log_text.hpp"

namespace mh {
namespace {

// The handles the host gave and has not withdrawn, in every engine of the
// process (never destroyed: an engine may outlive static destruction).
std::mutex& live_mutex() {
  static auto* m = new std::mutex;
  return *m;
}
std::unordered_set<const mh_host*>& live_hosts() {
  static auto* s = new std::unordered_set<const mh_host*>;
  return *s;
}
// Bumped whenever a handle is withdrawn. A thread's last validated handle is
// trusted while the generation it saw stands, so the time step's calls (the
// same handles again and again) take neither the lock nor the hash.
std::atomic<std::uint64_t> withdrawn_generation{0};
struct LastLive {
  const mh_host* host = nullptr;
  std::uint64_t generation = 0;
};
thread_local LastLive last_live;

// The instance behind `host`, or null (said on stderr: with no valid handle
// there is no instance to name) when the host did not give it.
InstanceHost* live(const mh_host* host, const char* service) {
  if (host != nullptr) {
    const std::uint64_t generation = withdrawn_generation.load(std::memory_order_acquire);
    if (host == last_live.host && generation == last_live.generation)
      return static_cast<InstanceHost*>(host->host_data);
    const std::lock_guard<std::mutex> lock(live_mutex());
    if (live_hosts().count(host) != 0) {
      last_live = {host, generation};
      return static_cast<InstanceHost*>(host->host_data);
    }
  }
  std::fprintf(stderr,
               "monohydra: a plugin called the host service %s with a handle the host did not "
               "give it (%s); the call is refused\n",
               service, host == nullptr ? "NULL" : "forged, or kept past its instance's destroy");
  return nullptr;
}

// A NULL out-pointer: refused and said, naming the service and the option.
mh_status no_place(const mh_host* host, const char* service, const char* key) {
  InstanceHost& h = *static_cast<InstanceHost*>(host->host_data);
  const std::string msg = std::string(service) + "('" + (key != nullptr ? key : "") +
                          "'): expected a place for the result, got NULL";
  h.engine->reports.last_plugin_error = h.source + ": " + msg;
  if (h.engine->reports.log) h.engine->reports.log(MH_LOG_ERROR, h.source, msg);
  return MH_ERROR;
}

void host_log(const mh_host* host, mh_log_level level, const char* message) {
  InstanceHost* hp = live(host, "log");
  if (hp == nullptr) return;
  InstanceHost& h = *hp;
  const std::string msg = log_text(message);
  if (level >= MH_LOG_ERROR) h.engine->reports.last_plugin_error = h.source + ": " + msg;
  if (h.engine->reports.log) h.engine->reports.log(level, h.source, msg);
}

const OptionValue* lookup(InstanceHost& h, const char* key) {
  if (key == nullptr || h.options == nullptr) return nullptr;
  h.keys_read.insert(key);
  auto it = h.options->find(key);
  return it == h.options->end() ? nullptr : &it->second;
}

std::string field_of(const InstanceHost& h, const char* key) {
  return h.source + " option '" + std::string(key != nullptr ? key : "") + "'";
}

// Reports an option error the way model-file errors are reported and keeps it
// for the InputError the engine throws after the plugin returns.
mh_status report(InstanceHost& h, const SourceMark& mark, const char* key,
                 const std::string& expected) {
  const InputError err(mark, field_of(h, key), expected);
  h.engine->reports.last_plugin_error = err.what();
  if (!h.engine->reports.option_error)
    h.engine->reports.option_error = std::make_unique<InputError>(err);
  if (h.engine->reports.log) h.engine->reports.log(MH_LOG_ERROR, h.source, err.what());
  return MH_ERROR;
}

mh_status missing(InstanceHost& h, const char* key, const char* what) {
  return report(h, h.mark, key, std::string("required option is missing (expected ") + what + ")");
}

mh_status host_option_number(const mh_host* host, const char* key, int required, double fallback,
                             double* out) {
  InstanceHost* hp = live(host, "option_number");
  if (hp == nullptr) return MH_ERROR;
  if (out == nullptr) return no_place(host, "option_number", key);
  InstanceHost& h = *hp;
  const OptionValue* v = lookup(h, key);
  if (v == nullptr) {
    if (required != 0) return missing(h, key, "a number");
    *out = fallback;
    return MH_OK;
  }
  if (v->kind != OptionValue::Kind::number || !std::isfinite(v->number))
    return report(h, v->mark, key, "expected a finite number, got '" + v->text + "'");
  *out = v->number;
  return MH_OK;
}

mh_status host_option_string(const mh_host* host, const char* key, int required,
                             const char* fallback, const char** out) {
  InstanceHost* hp = live(host, "option_string");
  if (hp == nullptr) return MH_ERROR;
  if (out == nullptr) return no_place(host, "option_string", key);
  InstanceHost& h = *hp;
  const OptionValue* v = lookup(h, key);
  if (v == nullptr) {
    if (required != 0) return missing(h, key, "a string");
    *out = fallback;
    return MH_OK;
  }
  if (v->kind != OptionValue::Kind::string)
    return report(h, v->mark, key, "expected a string, got '" + v->text + "'");
  *out = v->text.c_str();
  return MH_OK;
}

mh_status host_option_table(const mh_host* host, const char* key, int required, uint32_t columns,
                            const double** data, uint32_t* rows) {
  InstanceHost* hp = live(host, "option_table");
  if (hp == nullptr) return MH_ERROR;
  if (data == nullptr || rows == nullptr) return no_place(host, "option_table", key);
  InstanceHost& h = *hp;
  const OptionValue* v = lookup(h, key);
  const std::string expected = "a table of rows with " + std::to_string(columns) + " numbers each";
  if (v == nullptr) {
    if (required != 0) return missing(h, key, expected.c_str());
    *data = nullptr;
    *rows = 0;
    return MH_OK;
  }
  if (v->kind != OptionValue::Kind::table || v->columns != static_cast<int>(columns))
    return report(h, v->mark, key,
                  "expected " + expected + ", got " +
                      (v->kind == OptionValue::Kind::table ? std::to_string(v->columns) + " columns"
                                                           : "'" + v->text + "'"));
  *data = v->table.data();
  *rows = static_cast<uint32_t>(v->rows);
  return MH_OK;
}

mh_status host_option_error(const mh_host* host, const char* key, const char* expected) {
  InstanceHost* hp = live(host, "option_error");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  const OptionValue* v = lookup(h, key);
  const std::string got = v != nullptr ? ", got '" + v->text + "'" : "";
  return report(h, v != nullptr ? v->mark : h.mark, key,
                std::string("expected ") + (expected != nullptr ? expected : "") + got);
}

// A valid array of no elements: a mechanism without bodies has empty vectors,
// whose data() may be NULL, and NULL means "not given" to the other side.
const double* empty_array() {
  static const double kNone = 0.0;
  return &kNone;
}
const double* nonnull(const double* p) {
  return p != nullptr ? p : empty_array();
}

mh_status host_mech_info(const mh_host* host, mh_mech_info* out) {
  const InstanceHost* hp = live(host, "mech_info");
  if (hp == nullptr) return MH_ERROR;
  const Simulation::Engine& e = *hp->engine;
  mh_mech_info info{};
  info.struct_size = sizeof(info);
  info.num_coordinates = static_cast<uint32_t>(e.N);
  info.num_constraints = static_cast<uint32_t>(e.m);
  // A mechanism without bodies (a model of subsystems only) has empty arrays,
  // whose data() may be NULL: the table still points at valid (empty) arrays,
  // since NULL means "no information" to a formulation.
  static const char* const kNoName = "";
  static const uint8_t kNoAngle = 0;
  info.coordinate_names = e.N > 0 ? e.registry.coordinate_name_ptrs.data() : &kNoName;
  info.coordinate_is_angle = e.N > 0 ? e.registry.coordinate_is_angle.data() : &kNoAngle;
  info.position_tolerance = e.settings.tol_position;
  info.t0 = 0.0;
  info.z0 = e.N > 0 ? e.cons.z0.data() : empty_array();
  info.zd0 = e.N > 0 ? e.cons.zd0.data() : empty_array();
  return write_struct(out, info) ? MH_OK : MH_ERROR;
}

const char* role_name(InstanceHost::Role r) {
  switch (r) {
    case InstanceHost::Role::formulation:
      return "a formulation";
    case InstanceHost::Role::integrator:
      return "an integrator";
    case InstanceHost::Role::subsystem:
      break;
  }
  return "a subsystem";
}

// Services of the setup phase: only the roles named, only inside setup.
mh_status setup_only(InstanceHost& h, const char* what, bool subsystem, bool formulation) {
  const bool role_ok = (subsystem && h.role == InstanceHost::Role::subsystem) ||
                       (formulation && h.role == InstanceHost::Role::formulation);
  if (role_ok && h.in_setup) return MH_OK;
  const std::string who = subsystem && formulation ? "a subsystem or a formulation"
                          : subsystem              ? "a subsystem"
                                                   : "a formulation";
  host_log(&h.table, MH_LOG_ERROR,
           (std::string(what) + " may only be called by " + who + " during setup (called by " +
            role_name(h.role) + (h.in_setup ? ")" : " after setup)"))
               .c_str());
  return MH_ERROR;
}

void touch(SubsystemInstance& s, int index) {
  for (int t : s.touched)
    if (t == index) return;
  s.touched.push_back(index);
}

std::string text(const char* s) {
  return s != nullptr ? s : "";
}

// Declared states or outputs of one model at most: a plugin that declares
// without end is refused with the number, not left to exhaust the machine.
constexpr size_t kMaxDeclared = 1000000;

// A new state or output (`kind`), `count` of its kind already declared: at
// most kMaxDeclared of a kind, and each qualified name once (found in a set,
// so a plugin declaring many does not scan every earlier one).
bool declare_once(const mh_host* host, Simulation::Engine& e, const std::string& kind, size_t count,
                  const std::string& local, const std::string& qualified) {
  if (count >= kMaxDeclared) {
    host_log(host, MH_LOG_ERROR,
             ("add_" + kind + " '" + local + "': at most " + std::to_string(kMaxDeclared) + " " +
              kind + "s in a model; this would be one more")
                 .c_str());
    return false;
  }
  if (!e.states.declared_names.insert(kind + " " + qualified).second) {
    host_log(host, MH_LOG_ERROR, (kind + " '" + qualified + "' declared twice").c_str());
    return false;
  }
  return true;
}

// A role and range are optional; a range, when given, must be ordered.
bool valid_range(double lo, double hi) {
  return std::isfinite(lo) && std::isfinite(hi) && lo <= hi;
}

mh_status host_add_state(const mh_host* host, const mh_state_spec* spec_in, int32_t* index) {
  InstanceHost* hp = live(host, "add_state");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_state", true, false) != MH_OK) return MH_ERROR;
  const mh_state_spec spec = read_struct(spec_in);
  Simulation::Engine& e = *h.engine;
  SubsystemInstance& s = e.subsystems[static_cast<size_t>(h.subsystem)];
  const std::string local = text(spec.name);
  const std::string qualified = s.spec->name + "." + local;
  if (spec_in == nullptr || index == nullptr || local.empty() || !std::isfinite(spec.initial) ||
      !(spec.abs_tolerance > 0.0) || !valid_range(spec.range_min, spec.range_max)) {
    host_log(host, MH_LOG_ERROR,
             ("add_state '" + local +
              "': expected a name, a finite initial value, a positive tolerance and an ordered "
              "range")
                 .c_str());
    return MH_ERROR;
  }
  if (!declare_once(host, e, "state", e.states.state_info.size(), local, qualified))
    return MH_ERROR;
  auto named = s.spec->state_names.find(local);
  VariableInfo info;
  info.name = named != s.spec->state_names.end() ? named->second : qualified;
  info.qualified = qualified;
  info.unit = text(spec.unit);
  info.role = text(spec.role);
  info.range_min = spec.range_min;
  info.range_max = spec.range_max;
  const int i = e.add_state_record(info, spec.initial, spec.abs_tolerance);
  touch(s, i);
  *index = i;
  return MH_OK;
}

// The index of the state named `q` ("instance.state"), or -1.
int state_named(const Simulation::Engine& e, const std::string& q) {
  for (int i = 0; i < e.n_s; ++i)
    if (e.states.state_info[static_cast<size_t>(i)].qualified == q) return i;
  return -1;
}

mh_status host_find_state(const mh_host* host, const char* qualified_name, int32_t* index) {
  InstanceHost* hp = live(host, "find_state");
  if (hp == nullptr) return MH_ERROR;
  if (index == nullptr) return no_place(host, "find_state", qualified_name);
  InstanceHost& h = *hp;
  if (setup_only(h, "find_state", true, false) != MH_OK) return MH_ERROR;
  Simulation::Engine& e = *h.engine;
  const std::string q = text(qualified_name);
  const int i = state_named(e, q);
  if (i >= 0) {
    touch(e.subsystems[static_cast<size_t>(h.subsystem)], i);
    *index = i;
    return MH_OK;
  }
  host_log(
      host, MH_LOG_ERROR,
      ("no state '" + q + "' (states are found as 'instance.state' of instances above)").c_str());
  return MH_ERROR;
}

mh_status host_add_point(const mh_host* host, const char* key, int32_t* index) {
  InstanceHost* hp = live(host, "add_point");
  if (hp == nullptr) return MH_ERROR;
  if (index == nullptr) return no_place(host, "add_point", key);
  InstanceHost& h = *hp;
  if (setup_only(h, "add_point", true, false) != MH_OK) return MH_ERROR;
  SubsystemInstance& s = h.engine->subsystems[static_cast<size_t>(h.subsystem)];
  const std::string k = text(key);
  auto it = s.spec->points.find(k);
  if (it == s.spec->points.end()) {
    const InputError err(s.spec->mark, "subsystems '" + s.spec->name + "'.points",
                         "expected a point '" + k + "' ({body: NAME, at: [x, y, z]})");
    h.engine->reports.last_plugin_error = err.what();
    if (!h.engine->reports.option_error)
      h.engine->reports.option_error = std::make_unique<InputError>(err);
    if (h.engine->reports.log) h.engine->reports.log(MH_LOG_ERROR, h.source, err.what());
    return MH_ERROR;
  }
  s.points.push_back(it->second.point);
  s.p.resize(3 * s.points.size());
  s.v.resize(3 * s.points.size());
  s.f.resize(3 * s.points.size());
  *index = static_cast<int32_t>(s.points.size() - 1);
  return MH_OK;
}

mh_status host_add_output(const mh_host* host, const mh_output_spec* spec_in, int32_t* index) {
  InstanceHost* hp = live(host, "add_output");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_output", true, true) != MH_OK) return MH_ERROR;
  const mh_output_spec spec = read_struct(spec_in);
  Simulation::Engine& e = *h.engine;
  const bool from_subsystem = h.role == InstanceHost::Role::subsystem;
  const SubsystemSpec* owner =
      from_subsystem ? e.subsystems[static_cast<size_t>(h.subsystem)].spec : nullptr;
  const std::string local = text(spec.name);
  const std::string qualified = (from_subsystem ? owner->name : e.formulation_name) + "." + local;
  // A kind this host does not know (from a later minor version) is kept and
  // shown as a signal: the output still reaches the results.
  if (spec_in == nullptr || index == nullptr || local.empty() ||
      !valid_range(spec.range_min, spec.range_max)) {
    host_log(host, MH_LOG_ERROR,
             ("add_output '" + local + "': expected a name and an ordered range").c_str());
    return MH_ERROR;
  }
  if (!declare_once(host, e, "output", e.registry.output_info.size(), local, qualified))
    return MH_ERROR;
  VariableInfo info;
  info.qualified = qualified;
  info.name = qualified;
  if (owner != nullptr) {
    auto named = owner->output_names.find(local);
    if (named != owner->output_names.end()) info.name = named->second;
  }
  info.unit = text(spec.unit);
  info.kind = spec.kind;
  info.role = text(spec.role);
  info.range_min = spec.range_min;
  info.range_max = spec.range_max;
  e.registry.output_info.push_back(info);
  *index = e.n_o++;
  return MH_OK;
}

mh_status host_add_unknown(const mh_host* host, const mh_unknown_spec* spec_in, int32_t* index) {
  InstanceHost* hp = live(host, "add_unknown");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_unknown", false, true) != MH_OK) return MH_ERROR;
  const mh_unknown_spec spec = read_struct(spec_in);
  Simulation::Engine& e = *h.engine;
  const std::string name = text(spec.name);
  const bool kind_ok = spec.kind == MH_UNKNOWN_SECOND_ORDER ||
                       spec.kind == MH_UNKNOWN_FIRST_ORDER || spec.kind == MH_UNKNOWN_ALGEBRAIC;
  if (spec_in == nullptr || index == nullptr || name.empty() || !kind_ok ||
      !(spec.abs_tolerance > 0.0) || !std::isfinite(spec.abs_tolerance)) {
    host_log(host, MH_LOG_ERROR,
             ("add_unknown '" + name +
              "': expected a name, a kind (MH_UNKNOWN_SECOND_ORDER, _FIRST_ORDER or _ALGEBRAIC) "
              "and a positive, finite tolerance")
                 .c_str());
    return MH_ERROR;
  }
  e.registry.unknown_names.push_back(name);
  e.registry.unknown_kinds.push_back(static_cast<uint8_t>(spec.kind));
  e.registry.unknown_tol.conservativeResize(e.n_m + 1);
  e.registry.unknown_tol[e.n_m] = spec.abs_tolerance;
  *index = e.n_m++;
  return MH_OK;
}

mh_status host_evaluate_mechanics(const mh_host* host, const mh_mech_request* request,
                                  mh_mech_result* result) {
  InstanceHost* hp = live(host, "evaluate_mechanics");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  mh_mech_request rq = read_struct(request);
  const bool empty = h.engine->N == 0;  // no bodies: z and zd may be data() of empty vectors
  if (empty) rq.z = rq.z != nullptr ? rq.z : empty_array();
  if (empty) rq.zd = rq.zd != nullptr ? rq.zd : empty_array();
  if (h.role != InstanceHost::Role::formulation || request == nullptr || result == nullptr ||
      rq.z == nullptr || rq.zd == nullptr) {
    host_log(host, MH_LOG_ERROR, "evaluate_mechanics: for a formulation, with z and zd");
    return MH_ERROR;
  }
  Simulation::Engine& e = *h.engine;
  const mh_status s = e.evaluate_mechanics(rq.flags, rq.t, rq.z, rq.zd);
  const bool dyn = (rq.flags & MH_EVAL_DYNAMICS) != 0;
  const bool con = (rq.flags & MH_EVAL_CONSTRAINTS) != 0;
  mh_mech_result out{};
  out.struct_size = sizeof(out);
  out.M = dyn ? nonnull(e.data.M.data()) : nullptr;
  out.Q = dyn ? nonnull(e.data.Q.data()) : nullptr;
  out.phi = con ? nonnull(e.cons.phi.data()) : nullptr;
  out.phi_z = con ? nonnull(e.cons.phi_z.data()) : nullptr;
  out.phi_dot_zd =
      con && (rq.flags & MH_EVAL_POSITIONS_ONLY) == 0 ? nonnull(e.cons.phi_dot_zd.data()) : nullptr;
  if (!write_struct(result, out)) return MH_ERROR;
  return s;
}

// M' zdd - Q' in O(N) (inverse_dynamics.h).
mh_status host_inverse_dynamics(const mh_host* host, const mh_mech_request* request,
                                const double* zdd, double* r) {
  InstanceHost* hp = live(host, "inverse_dynamics");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  mh_mech_request rq = read_struct(request);
  Simulation::Engine& e = *h.engine;
  const bool empty = e.N == 0;
  if (empty) {
    rq.z = rq.z != nullptr ? rq.z : empty_array();
    rq.zd = rq.zd != nullptr ? rq.zd : empty_array();
    zdd = zdd != nullptr ? zdd : empty_array();
  }
  if (h.role != InstanceHost::Role::formulation || request == nullptr || rq.z == nullptr ||
      rq.zd == nullptr || zdd == nullptr || (r == nullptr && !empty)) {
    host_log(host, MH_LOG_ERROR, "inverse_dynamics: for a formulation, with z, zd, zdd and r");
    return MH_ERROR;
  }
  if ((rq.flags & ~(MH_EVAL_DYNAMICS | MH_EVAL_SUBSYSTEMS)) != 0) {
    host_log(host, MH_LOG_ERROR,
             "inverse_dynamics: flags: expected MH_EVAL_SUBSYSTEMS at most (the dynamics are "
             "implied; constraints are evaluate_mechanics's)");
    return MH_ERROR;
  }
  const mh_status s = e.evaluate_loads(rq.flags | MH_EVAL_DYNAMICS, rq.t, rq.z, rq.zd);
  if (!status_ok(s)) return s;
  if (empty) return MH_OK;
  inverse_dynamics(e.model, e.data, Eigen::Map<const Eigen::VectorXd>(zdd, e.N),
                   Eigen::Map<Eigen::VectorXd>(r, e.N));
  return MH_OK;
}

mh_status host_mech_derivatives(const mh_host* host, const mh_mech_derivatives_request* request,
                                mh_mech_derivatives* result) {
  InstanceHost* hp = live(host, "mech_derivatives");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  mh_mech_derivatives_request rq = read_struct(request);
  if (h.engine->N == 0) {  // no bodies: data() of empty vectors may be NULL
    rq.z = rq.z != nullptr ? rq.z : empty_array();
    rq.zd = rq.zd != nullptr ? rq.zd : empty_array();
    rq.zdd = rq.zdd != nullptr ? rq.zdd : empty_array();
  }
  const bool needs_zdd = (rq.flags & (MH_DERIV_DYNAMICS | MH_DERIV_CONSTRAINT_ACCELERATIONS)) != 0;
  const bool needs_v = (rq.flags & MH_DERIV_CONSTRAINT_FORCES) != 0;
  Simulation::Engine& e = *h.engine;
  if (h.role != InstanceHost::Role::formulation || h.in_setup || request == nullptr ||
      result == nullptr || rq.z == nullptr || rq.zd == nullptr ||
      (needs_zdd && rq.zdd == nullptr) || (needs_v && e.m > 0 && rq.v == nullptr)) {
    host_log(host, MH_LOG_ERROR,
             "mech_derivatives: for a formulation after its setup, with z, zd, and zdd or v "
             "where the flags need them");
    return MH_ERROR;
  }
  const mh_status s = e.mechanics_derivatives(rq);
  mh_mech_derivatives out{};
  out.struct_size = sizeof(out);
  const bool con = e.m > 0;
  out.K = (rq.flags & MH_DERIV_DYNAMICS) != 0 ? nonnull(e.work.derivs.K.data()) : nullptr;
  out.C = (rq.flags & MH_DERIV_DYNAMICS) != 0 ? nonnull(e.work.derivs.C.data()) : nullptr;
  out.dPhizT_v_dz = needs_v && con ? e.work.derivs.dPhizT_v_dz.data() : nullptr;
  const bool acc = (rq.flags & MH_DERIV_CONSTRAINT_ACCELERATIONS) != 0 && con;
  out.dA_dz = acc ? e.work.derivs.dA_dz.data() : nullptr;
  out.dA_dzd = acc ? e.work.derivs.dA_dzd.data() : nullptr;
  if (!write_struct(result, out)) return MH_ERROR;
  return s;
}

mh_status host_add_port(const mh_host* host, const mh_port_spec* spec, int32_t* index) {
  InstanceHost* hp = live(host, "add_port");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_port", true, false) != MH_OK) return MH_ERROR;
  if (spec == nullptr || index == nullptr) {
    host_log(host, MH_LOG_ERROR, "add_port: expected an mh_port_spec and an index");
    return MH_ERROR;
  }
  return h.engine->add_port(h, read_struct(spec), index);
}

// The point's world position at the assembled initial configuration (the
// constructor leaves the kinematics there while the instances are set up).
mh_status host_point_position(const mh_host* host, int32_t point, double* position3) {
  InstanceHost* hp = live(host, "point_position");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "point_position", true, false) != MH_OK) return MH_ERROR;
  const SubsystemInstance& s = h.engine->subsystems[static_cast<size_t>(h.subsystem)];
  if (point < 0 || static_cast<size_t>(point) >= s.points.size() || position3 == nullptr) {
    host_log(host, MH_LOG_ERROR, "point_position: no such point (add it with add_point first)");
    return MH_ERROR;
  }
  const Eigen::Vector3d p =
      mh::point_position(h.engine->data, s.points[static_cast<size_t>(point)]);
  for (int c = 0; c < 3; ++c) position3[c] = p[c];
  return MH_OK;
}

mh_status host_add_time_event(const mh_host* host, double t) {
  InstanceHost* hp = live(host, "add_time_event");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_time_event", true, false) != MH_OK) return MH_ERROR;
  if (!std::isfinite(t)) {
    host_log(host, MH_LOG_ERROR, "add_time_event: expected a finite time");
    return MH_ERROR;
  }
  h.engine->states.time_events.push_back(t);
  return MH_OK;
}

// option_signal (3.1) and option_signal_port (3.2): a table of rows [t,
// value], an input's name or, at a port, a state of the run. The value it
// hands out lives in the engine's Signals, written before each of the
// instance's calls (refresh_signals).
mh_status read_signal(const mh_host* host, const char* what, bool port, const char* key,
                      int required, double fallback, mh_signal* out) {
  InstanceHost* hp = live(host, what);
  if (hp == nullptr) return MH_ERROR;
  if (out == nullptr || out->struct_size < offsetof(mh_signal, value) + sizeof(out->value))
    return no_place(host, what, key);
  InstanceHost& h = *hp;
  if (setup_only(h, what, true, false) != MH_OK) return MH_ERROR;
  Simulation::Engine& e = *h.engine;
  Signals& signals = e.signals;
  SubsystemInstance& s = e.subsystems[static_cast<size_t>(h.subsystem)];
  const OptionValue* v = lookup(h, key);
  const std::string kinds = port ? "a number, a table of rows [t (s), value], an input's name or "
                                   "a state 'instance.state' of an instance above"
                                 : "a number, a table of rows [t (s), value] or an input's name";
  Signal signal;
  if (v == nullptr || v->kind == OptionValue::Kind::number) {
    if (v == nullptr && required != 0) return missing(h, key, kinds.c_str());
    // A number is a constant signal (what the option was before it was a
    // port), as is a missing one's fallback: written once, never refreshed.
    if (v != nullptr && !std::isfinite(v->number))
      return report(h, v->mark, key,
                    "expected a finite number or " + kinds + ", got '" + v->text + "'");
    signals.values.push_back(v != nullptr ? v->number : fallback);
    out->value = &signals.values.back();
    signals.constants.push_back({h.subsystem, key, &signals.values.back()});
    if (out->struct_size >= offsetof(mh_signal, state) + sizeof(out->state)) out->state = -1;
    return MH_OK;
  } else if (v->kind == OptionValue::Kind::string) {
    signal.input = signals.find_input(v->text);
    const int state = signal.input < 0 ? state_named(e, v->text) : -1;
    if (state >= 0 && !port)
      return report(h, v->mark, key,
                    "a table of rows [t (s), value] or one of the model's inputs, got '" + v->text +
                        "', a state of the run: this component reads the option with "
                        "option_signal (SDK 3.1), which takes no states (a signal port, "
                        "option_signal_port of SDK 3.2, does)");
    if (state >= 0) {
      signal.state = state;
      touch(s, state);
    } else if (signal.input < 0) {
      std::string known;
      for (const InputSignal& in : signals.inputs)
        known += (known.empty() ? "" : ", ") + in.spec->name;
      return report(
          h, v->mark, key,
          std::string(port ? "a table of rows [t (s), value], one of the model's "
                             "inputs (" +
                                 (known.empty() ? std::string("it declares none") : known) +
                                 ") or a state 'instance.state' of an instance "
                                 "listed above this one"
                           : "a table of rows [t (s), value] or one of the model's "
                             "inputs (" +
                                 (known.empty() ? std::string("it declares none") : known) + ")") +
              ", got '" + v->text + "'");
    } else {
      // The input's table jumps are events while the input follows it.
      const InputSignal& in = signals.inputs[static_cast<size_t>(signal.input)];
      bool read_before = false;
      for (const Signal& other : signals.list)
        read_before = read_before || other.input == signal.input;
      if (!read_before)
        for (double t : in.table.jump_times()) signals.input_events.emplace_back(t, signal.input);
    }
  } else {
    std::string error;
    if (v->kind != OptionValue::Kind::table || v->columns != 2 ||
        !signal.table.assign(v->table.data(), static_cast<uint32_t>(v->rows), error))
      return report(h, v->mark, key,
                    "expected " + (error.empty() ? kinds : error) + ", got '" + v->text + "'");
    for (double t : signal.table.jump_times()) e.states.time_events.push_back(t);
  }
  if (s.signals_end == 0) s.signals_begin = signals.list.size();
  signals.values.push_back(signal.state >= 0  ? e.states.y[signal.state]
                           : signal.input < 0 ? signal.table.value(0.0)
                                              : signals.input_value(signal.input, 0.0, e.run));
  signal.value = &signals.values.back();
  signals.list.push_back(std::move(signal));
  s.signals_end = signals.list.size();
  out->value = signals.list.back().value;
  if (out->struct_size >= offsetof(mh_signal, state) + sizeof(out->state))
    out->state = signals.list.back().state;
  return MH_OK;
}

mh_status host_option_signal(const mh_host* host, const char* key, int required, double fallback,
                             mh_signal* out) {
  return read_signal(host, "option_signal", false, key, required, fallback, out);
}

mh_status host_option_signal_port(const mh_host* host, const char* key, int required,
                                  double fallback, mh_signal* out) {
  return read_signal(host, "option_signal_port", true, key, required, fallback, out);
}

const char* host_model_folder(const mh_host* host) {
  const InstanceHost* hp = live(host, "model_folder");
  if (hp == nullptr || hp->engine->file == nullptr) return ".";
  return hp->engine->file->folder.empty() ? "." : hp->engine->file->folder.c_str();
}

// A component's look (visual.h): checked here, so that a host drawing it
// needs no checks of its own.
mh_status host_add_visual(const mh_host* host, const mh_visual_spec* spec_in) {
  InstanceHost* hp = live(host, "add_visual");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "add_visual", true, false) != MH_OK) return MH_ERROR;
  if (spec_in == nullptr) {
    host_log(host, MH_LOG_ERROR, "add_visual: expected a spec, got NULL");
    return MH_ERROR;
  }
  const mh_visual_spec spec = read_struct(spec_in);
  const SubsystemInstance& s = h.engine->subsystems[static_cast<size_t>(h.subsystem)];
  auto refuse = [&](const std::string& why) {
    host_log(host, MH_LOG_ERROR, ("add_visual: " + why).c_str());
    return MH_ERROR;
  };
  const bool actuator = spec.kind == MH_VISUAL_ACTUATOR;
  if (!actuator && spec.kind != MH_VISUAL_LINK)
    return refuse("unknown kind " + std::to_string(spec.kind) +
                  " (expected MH_VISUAL_ACTUATOR or MH_VISUAL_LINK)");
  const auto points = static_cast<int32_t>(s.points.size());
  for (const int32_t p : {spec.point_a, spec.point_b})
    if (p < 0 || p >= points)
      return refuse("no point " + std::to_string(p) + " (this instance added " +
                    std::to_string(points) + " with add_point)");
  if (spec.point_a == spec.point_b) return refuse("point_a and point_b are the same point");
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(spec.rod_diameter)) return refuse("expected a positive rod_diameter (m)");
  if (actuator && (!positive(spec.barrel_length) || !positive(spec.barrel_diameter)))
    return refuse("an actuator needs a positive barrel_length and barrel_diameter (m)");
  for (const int32_t state : {spec.state_a, spec.state_b})
    if (state < -1 || state >= h.engine->n_s)
      return refuse("no state " + std::to_string(state) + " (expected -1 or a global index below " +
                    std::to_string(h.engine->n_s) + ")");
  Visual v;
  v.instance = s.spec->name;
  v.kind = actuator ? Visual::Kind::actuator : Visual::Kind::link;
  v.a = s.points[static_cast<size_t>(spec.point_a)];
  v.b = s.points[static_cast<size_t>(spec.point_b)];
  v.barrel_length = actuator ? spec.barrel_length : 0.0;
  v.barrel_diameter = actuator ? spec.barrel_diameter : 0.0;
  v.rod_diameter = spec.rod_diameter;
  v.state_a = spec.state_a;
  v.state_b = spec.state_b;
  h.engine->registry.visuals.push_back(std::move(v));
  return MH_OK;
}

// The entries of an instance's jacobian block that may be non-zero
// (sparsity.h): both states touched, so that the block stays within the rows
// and columns the instance owns in the tangent.
mh_status host_declare_entries(const mh_host* host, uint32_t count, const int32_t* rows,
                               const int32_t* columns) {
  InstanceHost* hp = live(host, "declare_entries");
  if (hp == nullptr) return MH_ERROR;
  InstanceHost& h = *hp;
  if (setup_only(h, "declare_entries", true, false) != MH_OK) return MH_ERROR;
  if (count > 0 && (rows == nullptr || columns == nullptr)) {
    host_log(host, MH_LOG_ERROR, "declare_entries: expected rows and columns, got NULL");
    return MH_ERROR;
  }
  SubsystemInstance& s = h.engine->subsystems[static_cast<size_t>(h.subsystem)];
  auto touched = [&](int32_t state) {
    return std::find(s.touched.begin(), s.touched.end(), state) != s.touched.end();
  };
  for (uint32_t i = 0; i < count; ++i)
    for (const int32_t state : {rows[i], columns[i]})
      if (!touched(state)) {
        host_log(host, MH_LOG_ERROR,
                 ("declare_entries: entry " + std::to_string(i) + " names state " +
                  std::to_string(state) +
                  ", which this instance does not touch (expected a global index it added, "
                  "found or joined with a port before declaring)")
                     .c_str());
        return MH_ERROR;
      }
  for (uint32_t i = 0; i < count; ++i) s.declared.emplace_back(rows[i], columns[i]);
  return MH_OK;
}

// The mechanical block's pattern, for a formulation of coordinate unknowns
// once build_pattern has made it (sparsity.h).
mh_status host_mechanical_pattern(const mh_host* host, uint32_t* num_columns,
                                  const int32_t** column_start, const int32_t** row_index) {
  InstanceHost* hp = live(host, "mechanical_pattern");
  if (hp == nullptr) return MH_ERROR;
  if (num_columns == nullptr || column_start == nullptr || row_index == nullptr) {
    host_log(host, MH_LOG_ERROR,
             "mechanical_pattern: expected num_columns, column_start and row_index, got NULL");
    return MH_ERROR;
  }
  const auto& ws = hp->engine->work.tangent_ws;
  if (!ws.coordinate_unknowns || ws.mech_column_start.empty()) {
    host_log(host, MH_LOG_ERROR,
             ws.pattern == nullptr
                 ? "mechanical_pattern: called during setup (expected from the first residual "
                   "on: the host builds the pattern after setup)"
                 : "mechanical_pattern: this formulation does not declare "
                   "MH_EXT_COORDINATE_UNKNOWNS (its mechanical block is dense)");
    return MH_ERROR;
  }
  *num_columns = static_cast<uint32_t>(ws.mech_column_start.size() - 1);
  *column_start = ws.mech_column_start.data();
  *row_index = ws.mech_row_index.data();
  return MH_OK;
}

// The service tables, one per role's need (host.h): the functions are the
// same for every instance (each takes its mh_host), so the tables are too.
constexpr mh_options_service kOptions{sizeof(mh_options_service), host_option_number,
                                      host_option_string, host_option_table, host_option_error};
constexpr mh_mechanism_service kFormulationMechanism{
    sizeof(mh_mechanism_service), host_mech_info, host_evaluate_mechanics, host_mech_derivatives};
constexpr mh_mechanism_service kSubsystemMechanism{sizeof(mh_mechanism_service), host_mech_info,
                                                   nullptr, nullptr};
constexpr mh_outputs_service kOutputs{sizeof(mh_outputs_service), host_add_output};
constexpr mh_subsystem_setup_service kSubsystemSetup{sizeof(mh_subsystem_setup_service),
                                                     host_add_state,
                                                     host_find_state,
                                                     host_add_point,
                                                     host_add_port,
                                                     host_point_position,
                                                     host_add_time_event};
constexpr mh_unknowns_service kUnknowns{sizeof(mh_unknowns_service), host_add_unknown};
constexpr mh_model_folder_service kModelFolder{sizeof(mh_model_folder_service), host_model_folder};
constexpr mh_visual_service kVisual{sizeof(mh_visual_service), host_add_visual};
constexpr mh_sparsity_service kSparsity{sizeof(mh_sparsity_service), host_declare_entries};
constexpr mh_mechanical_pattern_service kMechanicalPattern{sizeof(mh_mechanical_pattern_service),
                                                           host_mechanical_pattern};
constexpr mh_inverse_dynamics_service kInverseDynamics{sizeof(mh_inverse_dynamics_service),
                                                       host_inverse_dynamics};
constexpr mh_signals_service kSignals{sizeof(mh_signals_service), host_option_signal,
                                      host_option_signal_port};

// What each role is given: integrators their options; formulations options,
// the mechanics, outputs and unknowns; subsystems options, mech_info,
// outputs and their place in the model.
const void* host_get_service(const mh_host* host, const char* id) {
  InstanceHost* hp = live(host, "get_service");
  if (hp == nullptr || id == nullptr) return nullptr;
  const InstanceHost::Role role = hp->role;
  const bool formulation = role == InstanceHost::Role::formulation;
  const bool subsystem = role == InstanceHost::Role::subsystem;
  if (std::strcmp(id, MH_SERVICE_OPTIONS) == 0) return &kOptions;
  if (std::strcmp(id, MH_SERVICE_MECHANISM) == 0)
    return formulation ? &kFormulationMechanism : subsystem ? &kSubsystemMechanism : nullptr;
  if (std::strcmp(id, MH_SERVICE_OUTPUTS) == 0)
    return formulation || subsystem ? &kOutputs : nullptr;
  if (std::strcmp(id, MH_SERVICE_SUBSYSTEM_SETUP) == 0)
    return subsystem ? &kSubsystemSetup : nullptr;
  if (std::strcmp(id, MH_SERVICE_UNKNOWNS) == 0) return formulation ? &kUnknowns : nullptr;
  if (std::strcmp(id, MH_SERVICE_SIGNALS) == 0) return subsystem ? &kSignals : nullptr;
  if (std::strcmp(id, MH_SERVICE_MODEL_FOLDER) == 0) return subsystem ? &kModelFolder : nullptr;
  if (std::strcmp(id, MH_SERVICE_VISUAL) == 0) return subsystem ? &kVisual : nullptr;
  if (std::strcmp(id, MH_SERVICE_SPARSITY) == 0) return subsystem ? &kSparsity : nullptr;
  if (std::strcmp(id, MH_SERVICE_MECHANICAL_PATTERN) == 0)
    return formulation ? &kMechanicalPattern : nullptr;
  if (std::strcmp(id, MH_SERVICE_INVERSE_DYNAMICS) == 0)
    return formulation ? &kInverseDynamics : nullptr;
  return nullptr;
}

}  // namespace

InstanceHost::~InstanceHost() {
  const std::lock_guard<std::mutex> lock(live_mutex());
  live_hosts().erase(&table);
  withdrawn_generation.fetch_add(1, std::memory_order_release);
}

void Simulation::Engine::make_host(InstanceHost& h, const std::string& source,
                                   const OptionMap* options, const SourceMark& mark,
                                   InstanceHost::Role role, int subsystem) {
  h.engine = this;
  h.source = source;
  h.options = options;
  h.mark = mark;
  h.role = role;
  h.subsystem = subsystem;
  h.table.struct_size = sizeof(mh_host);
  h.table.abi_version = MH_ABI_VERSION_INIT;
  h.table.host_data = &h;
  h.table.log = host_log;
  h.table.get_service = host_get_service;
  const std::lock_guard<std::mutex> lock(live_mutex());
  live_hosts().insert(&h.table);
}

int Simulation::Engine::add_state_record(const VariableInfo& info, double initial,
                                         double abs_tolerance) {
  const int i = n_s++;
  states.state_info.push_back(info);
  states.y.conservativeResize(n_s);
  states.y[i] = initial;
  states.state_tol.conservativeResize(n_s);
  states.state_tol[i] = abs_tolerance;
  return i;
}

void Simulation::Engine::check_unread_options(const InstanceHost& h) const {
  if (h.options == nullptr) return;
  for (const auto& [key, value] : *h.options) {
    if (h.keys_read.count(key) != 0) continue;
    std::string known;
    for (const auto& k : h.keys_read) known += (known.empty() ? "" : ", ") + k;
    throw InputError(value.mark, h.source + " option '" + key + "'",
                     "unknown option (expected one of: " + (known.empty() ? "none" : known) + ")");
  }
}

mh_subsystem_eval Simulation::Engine::subsystem_eval(double t_eval, double* rows) {
  mh_subsystem_eval ev{};
  ev.struct_size = sizeof(mh_subsystem_eval);
  ev.t = t_eval;
  ev.num_states = static_cast<uint32_t>(n_s);
  ev.y = states.y.data();
  ev.ydot = states.ydot.data();
  ev.residual = rows;
  ev.num_outputs = static_cast<uint32_t>(n_o);
  ev.outputs = registry.outputs.data();
  return ev;
}

void Simulation::Engine::point_at(mh_subsystem_eval& ev, SubsystemInstance& s) {
  ev.num_points = static_cast<uint32_t>(s.points.size());
  ev.num_touched = static_cast<uint32_t>(s.touched.size());
  ev.point_p = s.p.data();
  ev.point_v = s.v.data();
  ev.point_f = s.f.data();
}

mh_status Simulation::Engine::evaluate_subsystems(double t_eval, double* rows) {
  std::fill(rows, rows + n_s, 0.0);
  mh_subsystem_eval ev = subsystem_eval(t_eval, rows);
  double total_power = 0.0;
  for (auto& s : subsystems) {
    const size_t np = s.points.size();
    for (size_t k = 0; k < np; ++k) {
      const Eigen::Vector3d p = point_position(data, s.points[k]);
      const Eigen::Vector3d v = point_velocity(data, s.points[k]);
      for (int c = 0; c < 3; ++c) {
        s.p[3 * k + c] = p[c];
        s.v[3 * k + c] = v[c];
        s.f[3 * k + c] = 0.0;
      }
    }
    point_at(ev, s);
    const mh_status st = normalized(evaluate_instance(s, ev));
    if (!status_ok(st)) return st;
    s.power = 0.0;
    for (size_t k = 0; k < np; ++k) {
      const Eigen::Vector3d F(s.f[3 * k], s.f[3 * k + 1], s.f[3 * k + 2]);
      const Eigen::Vector3d p(s.p[3 * k], s.p[3 * k + 1], s.p[3 * k + 2]);
      const Eigen::Vector3d v(s.v[3 * k], s.v[3 * k + 1], s.v[3 * k + 2]);
      apply_point_force(data, s.points[k].body, p, F);
      if (s.points[k].body != kGround) s.power += F.dot(v);
    }
    total_power += s.power;
  }
  work.eval.power = total_power;
  return MH_OK;
}

// The kinematics at (zq, zdq), run only when `data` does not already hold
// them: a formulation asks for the same z several times per residual and
// tangent (the dependent coordinates' last check, M' and Q', derivatives).
void Simulation::Engine::kinematics_at(const double* zq, const double* zdq) {
  const Eigen::Map<const Eigen::VectorXd> zm(zq, N), zdm(zdq, N);
  const bool same_z = work.eval.kinematics_valid && data.z == zm;
  if (same_z && data.zd == zdm) return;
  work.eval.kin_zd = zdm;
  if (same_z) {
    // New rates at the same z (a projection of zd, a rate column): the
    // positions and rotations stand.
    forward_velocities(model, data, work.eval.kin_zd);
  } else {
    work.eval.kin_z = zm;
    forward_kinematics(model, data, work.eval.kin_z, work.eval.kin_zd);
  }
  work.eval.kinematics_valid = true;
  ++run.counters.kinematics_passes;
}

mh_status Simulation::Engine::evaluate_mechanics(uint32_t flags, double t_eval, const double* zq,
                                                 const double* zdq) {
  const mh_status st = evaluate_loads(flags, t_eval, zq, zdq);
  if (!status_ok(st)) return st;
  if ((flags & MH_EVAL_DYNAMICS) != 0) mass_matrix_and_forces(model, data);
  if ((flags & MH_EVAL_CONSTRAINTS) != 0)
    constraints_at_kinematics((flags & MH_EVAL_POSITIONS_ONLY) == 0);
  return MH_OK;
}

// The kinematics at (zq, zdq) and, for the dynamics or the iterate, the
// subsystems' forces on the bodies (and their rows).
mh_status Simulation::Engine::evaluate_loads(uint32_t flags, double t_eval, const double* zq,
                                             const double* zdq) {
  kinematics_at(zq, zdq);
  // The iterate's rows only inside a residual call (rows_target set); any
  // other evaluation leaves them alone.
  const bool iterate = (flags & MH_EVAL_SUBSYSTEMS) != 0 && work.eval.rows_target != nullptr;
  if ((flags & (MH_EVAL_DYNAMICS | MH_EVAL_SUBSYSTEMS)) != 0) {
    reset_applied_forces(model, data);
    const mh_status st = evaluate_subsystems(
        t_eval, iterate ? work.eval.rows_target : work.eval.scratch_rows.data());
    if (!status_ok(st)) return st;
    if (iterate) {
      work.eval.iterate_evaluated = true;
      work.eval.z_iterate =
          data.z;  // where the analytic coupling differentiates (subsystem_coupling.cpp)
      work.eval.zd_iterate = data.zd;
    }
  }
  return MH_OK;
}

void Simulation::Engine::constraints_at_kinematics(bool rates) {
  // Phi and Phi_z depend on z alone: new rates at the same z (double-step's
  // zd after its dependent coordinates converge) need only the velocity
  // terms, and a caller that reads positions only (MH_EVAL_POSITIONS_ONLY:
  // double-step's dependent solve, the accepted state's |Phi|) none.
  if (!(run.constraint_positions_valid && run.constraint_z == data.z)) {
    evaluate_constraint_positions(model, data, cons.constraints, cons.phi, cons.phi_z);
    run.constraint_z = data.z;  // sized N after the first call: no allocation after it
    run.constraint_positions_valid = true;
    run.constraint_rates_valid = false;
    ++run.counters.constraint_position_passes;
  }
  if (!rates || (run.constraint_rates_valid && run.constraint_zd == data.zd)) return;
  evaluate_constraint_velocity_terms(data, cons.constraints, cons.phi_dot_zd);
  run.constraint_zd = data.zd;
  run.constraint_rates_valid = true;
  ++run.counters.constraint_rate_passes;
}

}  // namespace mh
