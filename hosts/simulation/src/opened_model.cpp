#include "opened_model.hpp"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "model_plugins.hpp"
#include "model_settings.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_text.hpp"
#include "monohydra/core/run_limits.hpp"
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

ModelFile parse_changed(const OpenedModel& model, const std::string& text, const std::string& path,
                        const std::string& value) {
  try {
    return parse_model_text(text, model.label + " (with " + path + "=" + value + ")",
                            model.base_dir);
  } catch (const InputError& err) {
    throw std::invalid_argument(err.what());
  }
}

}  // namespace

OpenedModel::OpenedModel(const OpenRequest& request) {
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
  label = from_file ? request.path : request.label;
  base_dir =
      from_file ? std::filesystem::path(request.path).parent_path().string() : request.base_dir;
  if (base_dir.empty()) base_dir = ".";
  text = from_file ? read_model_text(request.path) : request.text;
  std::string parsed_label = label;
  if (!paths.empty()) {
    // Values by path are set in the model's text before the parser reads it,
    // as run --set sets them, so a bad value gets the parser's own checks at
    // the line that holds it.
    host::SetText set;
    try {
      set = host::apply_settings(text, label, paths);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument(std::string("setting ") + err.what());
    }
    text = set.text;
    if (set.rewritten) parsed_label += " (as the settings rewrote it)";
  }
  file = parse_model_text(text, parsed_label, base_dir);
  {
    const std::lock_guard<std::mutex> lock(open_mutex());
    host::load_model_plugins(file, registry);
  }
  SolverSettings planned = file.solver;
  if (choices.dt) planned.dt = *choices.dt;
  if (choices.t_end) planned.t_end = *choices.t_end;
  check_run_settings(file, planned, RunLimits{}, 0);
}

void set_parameter(Simulation& sim, const OpenedModel& opened, ChangedModel& run,
                   const std::string& path, const std::string& value) {
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
  const host::SetText set = host::apply_settings(run.text, opened.label, {{path, value}});
  const ModelFile changed = parse_changed(opened, set.text, path, value);
  if (option) {
    // The component changes it (monohydra/parameters.h) or says why not; the
    // text follows only once it has.
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
    sim.set_component_parameter(parts[1], key, number);
    run.text = set.text;
    return;
  }
  Model& now = run.model;  // as the run's file reads before this change
  if (changed.model.bodies.size() != now.bodies.size())
    throw std::invalid_argument(path + ": the changed model has other bodies");
  if (initial) {
    // In the parsed model's units (rad, m): the engine closes the loops
    // around it, or refuses and keeps what it had.
    for (size_t j = 0; j < now.bodies.size(); ++j) {
      const Body& b = changed.model.bodies[j];
      Body& kept = now.bodies[j];
      if (b.z0 == kept.z0 && b.zd0 == kept.zd0) continue;
      sim.set_initial_state(static_cast<int>(j), b.z0, b.zd0);
      kept.z0 = b.z0;
      kept.zd0 = b.zd0;
    }
    run.text = set.text;
    return;
  }
  std::vector<int> bodies;
  for (size_t j = 0; j < now.bodies.size(); ++j) {
    const Body& a = now.bodies[j];
    const Body& b = changed.model.bodies[j];
    if (a.mass != b.mass || a.com_B != b.com_B || a.inertia_B != b.inertia_B)
      bodies.push_back(static_cast<int>(j));
  }
  for (const int j : bodies) {
    const Body& b = changed.model.bodies[static_cast<size_t>(j)];
    sim.set_body_inertia(j, b.mass, b.com_B, b.inertia_B);
    Body& kept = now.bodies[static_cast<size_t>(j)];
    kept.mass = b.mass;
    kept.com_B = b.com_B;
    kept.inertia_B = b.inertia_B;
  }
  if (changed.model.gravity != now.gravity) {
    sim.set_gravity(changed.model.gravity);
    now.gravity = changed.model.gravity;
  }
  run.text = set.text;
}

}  // namespace mh::embed
