// A study addresses a model's value by its path in the model's normalized
// form: lists of named items by name (subsystems/valve/flow_coefficient,
// bodies/body1/mass), other lists by index, and `formulation` / `integrator`
// as a mapping whether the file writes `formulation: penalty` or
// `{name: penalty}` (formulation/name). Overrides are applied to the YAML tree
// before the model parser reads it, so a bad value gets the parser's checks.
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

namespace mh::host {

// "a/b/c" into {"a", "b", "c"}; empty segments are refused by check_path.
std::vector<std::string> split_path(const std::string& path);

// Why `path` cannot be set in the model tree `root` ("" when it can): a
// segment that is not there, with what is there instead. Beyond values the
// file writes, a path may name solver settings (solver/dt, solver/t_end,
// solver/max_iterations, solver/max_step_halvings, solver/tol_position) and
// the name or an option of formulation and integrator.
std::string check_path(const YAML::Node& root, const std::string& path);

// The node the file writes at `path` (with its mark), by the same walk;
// none when the file writes nothing there (a solver setting or a component
// option it leaves out, or a path that is not in the model).
std::optional<YAML::Node> value_at(const YAML::Node& root, const std::string& path);

// Sets the value at `path` in `root` (normalizing formulation and integrator
// first). Throws std::invalid_argument with check_path's reason.
void set_path(YAML::Node& root, const std::string& path, const YAML::Node& value);

}  // namespace mh::host
