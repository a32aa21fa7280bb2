#include "instance.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "model_plugins.hpp"
#include "model_settings.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_text.hpp"
#include "monohydra/core/run_limits.hpp"
#include "parameter_direction.hpp"
#include "parameter_path.hpp"

namespace mh::embed {

namespace {

// Loading plugins probes each new library in a forked child and writes the
// probe cache: one open at a time in a process, so that no fork happens
// while another thread of ours holds a lock the child would need.
std::mutex& open_mutex() {
  static std::mutex m;
  return m;
}

double seconds(const std::string& path, const std::string& text) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, v);
  if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v) || !(v > 0.0))
    throw std::invalid_argument("setting '" + path + "': '" + text +
                                "' is not a positive number of seconds");
  return v;
}

}  // namespace

Instance::Instance(const OpenRequest& request) {
  RunChoices choices;
  std::vector<host::PathSetting> paths;
  for (const auto& [path, value] : request.settings) {
    if (path == "formulation")
      choices.formulation = value;
    else if (path == "integrator")
      choices.integrator = value;
    else if (path == "dt")
      choices.dt = seconds(path, value);
    else if (path == "t_end")
      choices.t_end = seconds(path, value);
    else
      paths.push_back({path, value});
  }
  const bool from_file = !request.path.empty();
  label_ = from_file ? request.path : request.label;
  base_dir_ =
      from_file ? std::filesystem::path(request.path).parent_path().string() : request.base_dir;
  if (base_dir_.empty()) base_dir_ = ".";
  text_ = from_file ? read_model_text(request.path) : request.text;
  std::string label = label_;
  if (!paths.empty()) {
    // Values by path are set in the model's text before the parser reads it,
    // as run --set sets them, so a bad value gets the parser's own checks at
    // the line that holds it.
    host::SetText set;
    try {
      set = host::apply_settings(text_, label_, paths);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument(std::string("setting ") + err.what());
    }
    text_ = set.text;
    if (set.rewritten) label += " (as the settings rewrote it)";
  }
  file_ = parse_model_text(text_, label, base_dir_);
  {
    const std::lock_guard<std::mutex> lock(open_mutex());
    host::load_model_plugins(file_, registry_);
  }
  SolverSettings planned = file_.solver;
  if (choices.dt) planned.dt = *choices.dt;
  if (choices.t_end) planned.t_end = *choices.t_end;
  check_run_settings(file_, planned, RunLimits{}, 0);
  // Plugins' warnings reach the caller as the call's MHS_WARNING.
  const LogSink log = [this](mh_log_level level, const std::string& source,
                             const std::string& text) {
    if (level < MH_LOG_WARNING) return;
    if (!warnings.empty()) warnings += '\n';
    warnings += source + ": " + text;
  };
  sim_ = std::make_unique<Simulation>(file_, registry_, choices, log);
  layout_ = std::make_unique<CsvLayout>(*sim_, file_.output, std::nullopt);
  check_column_names(file_, *sim_);
  make_variables();
}

void Instance::set_parameter(const std::string& path, const std::string& value) {
  const std::vector<std::string> parts = host::split_path(path);
  const bool body_value =
      parts.size() >= 3 && parts[0] == "bodies" &&
      (parts[2] == "mass" || parts[2] == "com" || parts[2] == "inertia" || parts[2] == "payload");
  const bool initial =
      parts.size() == 3 && parts[0] == "bodies" && (parts[2] == "z0" || parts[2] == "zd0");
  const bool gravity = parts.size() <= 2 && parts[0] == "gravity";
  const bool option = parts.size() >= 3 && parts[0] == "subsystems";  // a table's entry too
  if (!body_value && !initial && !gravity && !option)
    throw std::invalid_argument(path +
                                ": not a value that changes during a run; in place change a "
                                "body's mass, com, inertia and payload, gravity, and the options a "
                                "component changes in place, and before the run starts a body's "
                                "z0 and zd0 (open the model with this setting)");
  const host::SetText set = host::apply_settings(text_, label_, {{path, value}});
  if (option) {
    // The component changes it (monohydra/parameters.h) or says why not; the
    // text follows only once it has.
    ModelFile changed;
    try {
      changed =
          parse_model_text(set.text, label_ + " (with " + path + "=" + value + ")", base_dir_);
    } catch (const InputError& err) {
      throw std::invalid_argument(err.what());
    }
    double number = 0.0;
    std::string key = parts[2];
    if (parts.size() == 3) {
      for (const SubsystemSpec& spec : changed.subsystems)
        if (spec.name == parts[1]) number = spec.options.at(parts[2]).number;
    } else {  // an entry of a table (flow_table/3/2): the number the file now writes there
      for (size_t k = 3; k < parts.size(); ++k) key += "/" + parts[k];
      const std::optional<YAML::Node> node = host::value_at(YAML::Load(set.text), path);
      if (!node || !node->IsScalar())
        throw std::invalid_argument(path + ": the model file writes no number there");
      number = node->as<double>();
    }
    sim_->set_component_parameter(parts[1], key, number);
    text_ = set.text;
    return;
  }
  ModelFile changed;
  try {
    changed = parse_model_text(set.text, label_ + " (with " + path + "=" + value + ")", base_dir_);
  } catch (const InputError& err) {
    throw std::invalid_argument(err.what());
  }
  Model& model = file_.model;
  if (changed.model.bodies.size() != model.bodies.size())
    throw std::invalid_argument(path + ": the changed model has other bodies");
  if (initial) {
    // In the parsed model's units (rad, m): the engine closes the loops
    // around it, or refuses and keeps what it had.
    for (size_t j = 0; j < model.bodies.size(); ++j) {
      const Body& b = changed.model.bodies[j];
      Body& kept = model.bodies[j];
      if (b.z0 == kept.z0 && b.zd0 == kept.zd0) continue;
      sim_->set_initial_state(static_cast<int>(j), b.z0, b.zd0);
      kept.z0 = b.z0;
      kept.zd0 = b.zd0;
    }
    text_ = set.text;
    return;
  }
  // Everything is checked before anything changes.
  std::vector<int> bodies;
  for (size_t j = 0; j < model.bodies.size(); ++j) {
    const Body& a = model.bodies[j];
    const Body& b = changed.model.bodies[j];
    if (a.mass != b.mass || a.com_B != b.com_B || a.inertia_B != b.inertia_B)
      bodies.push_back(static_cast<int>(j));
  }
  for (const int j : bodies) {
    const Body& b = changed.model.bodies[static_cast<size_t>(j)];
    sim_->set_body_inertia(j, b.mass, b.com_B, b.inertia_B);
    Body& kept = model.bodies[static_cast<size_t>(j)];
    kept.mass = b.mass;
    kept.com_B = b.com_B;
    kept.inertia_B = b.inertia_B;
  }
  if (changed.model.gravity != model.gravity) {
    sim_->set_gravity(changed.model.gravity);
    model.gravity = changed.model.gravity;
  }
  text_ = set.text;
}

void Instance::make_variables() {
  const auto& names = sim_->coordinate_names();
  for (size_t i = 0; i < names.size(); ++i) {
    const bool angle = file_.model.bodies[i].joint == JointType::revolute;
    variables_.push_back(
        {MHS_COORDINATE, static_cast<int>(i), names[i], names[i], angle ? "rad" : "m"});
    variables_.push_back({MHS_COORDINATE_RATE, static_cast<int>(i), names[i] + "_dot",
                          names[i] + "_dot", angle ? "rad/s" : "m/s"});
  }
  // Coordinates and their rates side by side above; the documented order
  // is all coordinates, then all rates.
  std::stable_partition(variables_.begin(), variables_.end(),
                        [](const Variable& v) { return v.kind == MHS_COORDINATE; });
  const auto add = [&](mhs_kind kind, const std::vector<VariableInfo>& infos) {
    for (size_t i = 0; i < infos.size(); ++i) {
      const VariableInfo& info = infos[i];
      Variable v{kind, static_cast<int>(i), info.name.empty() ? info.qualified : info.name,
                 info.qualified, info.unit};
      if (info.range_min < info.range_max) {
        v.min = info.range_min;
        v.max = info.range_max;
      }
      variables_.push_back(v);
    }
  };
  add(MHS_STATE, sim_->state_info());
  add(MHS_OUTPUT, sim_->output_info());
  const std::vector<InputSpec>& inputs = sim_->inputs();
  for (size_t k = 0; k < inputs.size(); ++k)
    variables_.push_back({MHS_INPUT, static_cast<int>(k), inputs[k].name,
                          "inputs." + inputs[k].name, inputs[k].unit, inputs[k].min,
                          inputs[k].max});
  for (size_t k = 0; k < variables_.size(); ++k) {
    by_name_.emplace(variables_[k].qualified, static_cast<int>(k));
    by_name_.emplace(variables_[k].name, static_cast<int>(k));
  }
}

int Instance::find(const std::string& name) const {
  const auto it = by_name_.find(name);
  return it == by_name_.end() ? -1 : it->second;
}

ParameterDirection Instance::parameter(const std::string& path) const {
  return host::parameter_direction(text_, label_, base_dir_, file_, path);
}

void Instance::track_sensitivities(const std::vector<std::string>& paths) {
  std::vector<ParameterDirection> directions;
  directions.reserve(paths.size());
  for (const std::string& path : paths) directions.push_back(parameter(path));
  sim_->track_sensitivities(directions);
}

double Instance::sensitivity(const Variable& v, int j) const {
  switch (v.kind) {
    case MHS_COORDINATE:
      return sim_->coordinate_sensitivities()(v.index, j);
    case MHS_COORDINATE_RATE:
      return sim_->coordinate_rate_sensitivities()(v.index, j);
    case MHS_STATE:
      return sim_->state_sensitivities()(v.index, j);
    case MHS_OUTPUT:
      if (sim_->output_differentiated(v.index)) return sim_->output_sensitivities()(v.index, j);
      break;
    default:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double Instance::value(const Variable& v) const {
  switch (v.kind) {
    case MHS_COORDINATE:
      return sim_->z()[v.index];
    case MHS_COORDINATE_RATE:
      return sim_->zd()[v.index];
    case MHS_STATE:
      return sim_->states()[v.index];
    case MHS_INPUT:
      return sim_->input(v.index);
    default:
      return sim_->outputs()[v.index];
  }
}

const std::string& Instance::row_text(bool header) const {
  row_stream_.str("");
  if (header)
    layout_->header(row_stream_);
  else
    layout_->row(row_stream_, *sim_);
  row_ = row_stream_.str();
  return row_;
}

}  // namespace mh::embed
