// The mh_host table the core hands to every plugin instance: options from the
// model file, logging, state and point registration, and the semirecursive
// kinematics and dynamics. No exception crosses the C boundary.
#include <cmath>
#include <cstring>

#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {
namespace {

InstanceHost& self(const mh_host* host) {
  return *static_cast<InstanceHost*>(host->host_data);
}

void host_log(const mh_host* host, mh_log_level level, const char* message) {
  InstanceHost& h = self(host);
  const std::string msg = message != nullptr ? message : "";
  if (level >= MH_LOG_ERROR) h.engine->last_plugin_error = h.source + ": " + msg;
  if (h.engine->log) h.engine->log(level, h.source, msg);
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
  h.engine->last_plugin_error = err.what();
  if (!h.engine->option_error) h.engine->option_error = std::make_unique<InputError>(err);
  if (h.engine->log) h.engine->log(MH_LOG_ERROR, h.source, err.what());
  return MH_ERROR;
}

mh_status missing(InstanceHost& h, const char* key, const char* what) {
  return report(h, h.mark, key, std::string("required option is missing (expected ") + what + ")");
}

mh_status host_option_number(const mh_host* host, const char* key, int required, double fallback,
                             double* out) {
  InstanceHost& h = self(host);
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
  InstanceHost& h = self(host);
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
  InstanceHost& h = self(host);
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
  InstanceHost& h = self(host);
  const OptionValue* v = lookup(h, key);
  const std::string got = v != nullptr ? ", got '" + v->text + "'" : "";
  return report(h, v != nullptr ? v->mark : h.mark, key,
                std::string("expected ") + (expected != nullptr ? expected : "") + got);
}

mh_status host_mech_info(const mh_host* host, mh_mech_info* out) {
  if (out == nullptr || out->struct_size < sizeof(mh_mech_info)) return MH_ERROR;
  const Simulation::Engine& e = *self(host).engine;
  out->num_coordinates = static_cast<uint32_t>(e.N);
  out->num_constraints = static_cast<uint32_t>(e.m);
  out->coordinate_names = e.coordinate_name_ptrs.data();
  out->coordinate_is_angle = e.coordinate_is_angle.data();
  out->position_tolerance = e.settings.tol_position;
  out->dt = e.settings.dt;
  out->z0 = e.z0.data();
  out->zd0 = e.zd0.data();
  return MH_OK;
}

mh_status setup_only(InstanceHost& h, const char* what) {
  if (h.subsystem >= 0 && h.in_setup) return MH_OK;
  host_log(&h.table, MH_LOG_ERROR,
           (std::string(what) + " may only be called by a subsystem during setup").c_str());
  return MH_ERROR;
}

void touch(SubsystemInstance& s, int index) {
  for (int t : s.touched)
    if (t == index) return;
  s.touched.push_back(index);
}

mh_status host_add_state(const mh_host* host, const char* name, double initial,
                         double abs_tolerance, const char* unit, int32_t* index) {
  InstanceHost& h = self(host);
  if (setup_only(h, "add_state") != MH_OK) return MH_ERROR;
  Simulation::Engine& e = *h.engine;
  SubsystemInstance& s = e.subsystems[static_cast<size_t>(h.subsystem)];
  const std::string local = name != nullptr ? name : "";
  const std::string qualified = s.spec->name + "." + local;
  if (local.empty() || !std::isfinite(initial) || !(abs_tolerance > 0.0)) {
    host_log(host, MH_LOG_ERROR,
             ("add_state '" + local +
              "': expected a name, a finite initial value and a positive tolerance")
                 .c_str());
    return MH_ERROR;
  }
  for (const auto& q : e.state_qualified)
    if (q == qualified) {
      host_log(host, MH_LOG_ERROR, ("state '" + qualified + "' declared twice").c_str());
      return MH_ERROR;
    }
  auto named = s.spec->state_names.find(local);
  const int i = e.n_s++;
  e.state_qualified.push_back(qualified);
  e.state_names.push_back(named != s.spec->state_names.end() ? named->second : qualified);
  e.state_units.push_back(unit != nullptr ? unit : "");
  e.y.conservativeResize(e.n_s);
  e.y[i] = initial;
  e.state_tol.conservativeResize(e.n_s);
  e.state_tol[i] = abs_tolerance;
  touch(s, i);
  *index = i;
  return MH_OK;
}

mh_status host_find_state(const mh_host* host, const char* qualified_name, int32_t* index) {
  InstanceHost& h = self(host);
  if (setup_only(h, "find_state") != MH_OK) return MH_ERROR;
  Simulation::Engine& e = *h.engine;
  const std::string q = qualified_name != nullptr ? qualified_name : "";
  for (int i = 0; i < e.n_s; ++i) {
    if (e.state_qualified[static_cast<size_t>(i)] == q) {
      touch(e.subsystems[static_cast<size_t>(h.subsystem)], i);
      *index = i;
      return MH_OK;
    }
  }
  host_log(
      host, MH_LOG_ERROR,
      ("no state '" + q + "' (states are found as 'instance.state' of instances above)").c_str());
  return MH_ERROR;
}

mh_status host_add_point(const mh_host* host, const char* key, int32_t* index) {
  InstanceHost& h = self(host);
  if (setup_only(h, "add_point") != MH_OK) return MH_ERROR;
  SubsystemInstance& s = h.engine->subsystems[static_cast<size_t>(h.subsystem)];
  const std::string k = key != nullptr ? key : "";
  auto it = s.spec->points.find(k);
  if (it == s.spec->points.end()) {
    const InputError err(s.spec->mark, "subsystems '" + s.spec->name + "'.points",
                         "expected a point '" + k + "' ({body: NAME, at: [x, y, z]})");
    h.engine->last_plugin_error = err.what();
    if (!h.engine->option_error) h.engine->option_error = std::make_unique<InputError>(err);
    if (h.engine->log) h.engine->log(MH_LOG_ERROR, h.source, err.what());
    return MH_ERROR;
  }
  s.points.push_back(it->second.point);
  s.p.resize(3 * s.points.size());
  s.v.resize(3 * s.points.size());
  s.f.resize(3 * s.points.size());
  *index = static_cast<int32_t>(s.points.size() - 1);
  return MH_OK;
}

mh_status host_add_output(const mh_host* host, const char* name, const char* unit, int32_t* index) {
  InstanceHost& h = self(host);
  if (setup_only(h, "add_output") != MH_OK) return MH_ERROR;
  Simulation::Engine& e = *h.engine;
  const SubsystemInstance& s = e.subsystems[static_cast<size_t>(h.subsystem)];
  const std::string local = name != nullptr ? name : "";
  const std::string qualified = s.spec->name + "." + local;
  for (const auto& q : e.output_qualified)
    if (local.empty() || q == qualified) {
      host_log(host, MH_LOG_ERROR,
               ("output '" + qualified + "' is empty or declared twice").c_str());
      return MH_ERROR;
    }
  auto named = s.spec->output_names.find(local);
  e.output_qualified.push_back(qualified);
  e.output_names.push_back(named != s.spec->output_names.end() ? named->second : qualified);
  e.output_units.push_back(unit != nullptr ? unit : "");
  *index = e.n_o++;
  return MH_OK;
}

mh_status host_evaluate_mechanics(const mh_host* host, const mh_mech_request* request,
                                  mh_mech_result* result) {
  InstanceHost& h = self(host);
  if (h.subsystem >= 0 || request == nullptr || result == nullptr || request->z == nullptr ||
      request->zd == nullptr) {
    host_log(host, MH_LOG_ERROR, "evaluate_mechanics: formulation only, with z and zd");
    return MH_ERROR;
  }
  Simulation::Engine& e = *h.engine;
  const mh_status s = e.evaluate_mechanics(request->flags, request->t, request->z, request->zd);
  const bool dyn = (request->flags & MH_EVAL_DYNAMICS) != 0;
  const bool con = (request->flags & MH_EVAL_CONSTRAINTS) != 0;
  result->M = dyn ? e.data.M.data() : nullptr;
  result->Q = dyn ? e.data.Q.data() : nullptr;
  result->phi = con ? e.phi.data() : nullptr;
  result->phi_z = con ? e.phi_z.data() : nullptr;
  result->phi_dot_zd = con ? e.phi_dot_zd.data() : nullptr;
  return s;
}

mh_status host_add_port(const mh_host* host, const mh_port_spec* spec, int32_t* index) {
  InstanceHost& h = self(host);
  if (setup_only(h, "add_port") != MH_OK) return MH_ERROR;
  if (spec == nullptr || spec->struct_size < sizeof(mh_port_spec) || index == nullptr) {
    host_log(host, MH_LOG_ERROR, "add_port: expected an mh_port_spec and an index");
    return MH_ERROR;
  }
  return h.engine->add_port(h, *spec, index);
}

// The point's world position at the assembled initial configuration (the
// constructor leaves the kinematics there while the instances are set up).
mh_status host_point_position(const mh_host* host, int32_t point, double* position3) {
  InstanceHost& h = self(host);
  if (setup_only(h, "point_position") != MH_OK) return MH_ERROR;
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
  InstanceHost& h = self(host);
  if (setup_only(h, "add_time_event") != MH_OK) return MH_ERROR;
  if (!std::isfinite(t)) {
    host_log(host, MH_LOG_ERROR, "add_time_event: expected a finite time");
    return MH_ERROR;
  }
  h.engine->time_events.push_back(t);
  return MH_OK;
}

const void* host_get_extension(const mh_host*, const char*) {
  return nullptr;
}

}  // namespace

void Simulation::Engine::make_host(InstanceHost& h, const std::string& source,
                                   const OptionMap* options, const SourceMark& mark,
                                   int subsystem) {
  h.engine = this;
  h.source = source;
  h.options = options;
  h.mark = mark;
  h.subsystem = subsystem;
  h.table.struct_size = sizeof(mh_host);
  h.table.abi_version = MH_ABI_VERSION_INIT;
  h.table.host_data = &h;
  h.table.log = host_log;
  h.table.option_number = host_option_number;
  h.table.option_string = host_option_string;
  h.table.option_table = host_option_table;
  h.table.option_error = host_option_error;
  h.table.mech_info = host_mech_info;
  h.table.add_state = host_add_state;
  h.table.find_state = host_find_state;
  h.table.add_point = host_add_point;
  h.table.add_output = host_add_output;
  h.table.evaluate_mechanics = host_evaluate_mechanics;
  h.table.get_extension = host_get_extension;
  h.table.add_port = host_add_port;
  h.table.point_position = host_point_position;
  h.table.add_time_event = host_add_time_event;
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
  ev.y = y.data();
  ev.ydot = ydot.data();
  ev.residual = rows;
  ev.num_outputs = static_cast<uint32_t>(n_o);
  ev.outputs = outputs.data();
  return ev;
}

void Simulation::Engine::point_at(mh_subsystem_eval& ev, SubsystemInstance& s) {
  ev.num_points = static_cast<uint32_t>(s.points.size());
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
    const mh_status st = s.api->evaluate(s.api, &ev);
    if (st >= MH_DISCARD) return st;
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
  power = total_power;
  return MH_OK;
}

mh_status Simulation::Engine::evaluate_mechanics(uint32_t flags, double t_eval, const double* zq,
                                                 const double* zdq) {
  const Eigen::Map<const Eigen::VectorXd> zm(zq, N), zdm(zdq, N);
  data.z = zm;
  data.zd = zdm;
  forward_kinematics(model, data, data.z, data.zd);
  const bool iterate = (flags & MH_EVAL_SUBSYSTEMS) != 0;
  if ((flags & (MH_EVAL_DYNAMICS | MH_EVAL_SUBSYSTEMS)) != 0) {
    reset_applied_forces(model, data);
    const mh_status st = evaluate_subsystems(t_eval, iterate ? rows_target : scratch_rows.data());
    if (st >= MH_DISCARD) return st;
    if (iterate) iterate_evaluated = true;
  }
  if ((flags & MH_EVAL_DYNAMICS) != 0) mass_matrix_and_forces(model, data);
  if ((flags & MH_EVAL_CONSTRAINTS) != 0)
    evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
  return MH_OK;
}

void Simulation::Engine::energy_terms(double& stored_out, double& dissipation_out) {
  stored_out = 0.0;
  dissipation_out = 0.0;
  mh_subsystem_eval ev = subsystem_eval(t, scratch_rows.data());
  for (auto& s : subsystems) {
    if (s.api->energy == nullptr) continue;
    point_at(ev, s);
    double st = 0.0, diss = 0.0;
    if (s.api->energy(s.api, &ev, &st, &diss) < MH_DISCARD) {
      stored_out += st;
      dissipation_out += diss;
    }
  }
}

}  // namespace mh
