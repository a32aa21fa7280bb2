#include "sensitivity_columns.hpp"

#include "model_settings.hpp"
#include "monohydra/core/model_text.hpp"
#include "parameter_direction.hpp"

namespace mh::cli {

std::vector<SensitivityColumn> sensitivity_columns(const Simulation& sim) {
  using Kind = SensitivityColumn::Kind;
  std::vector<SensitivityColumn> out;
  const auto& coordinates = sim.coordinate_names();
  for (size_t i = 0; i < coordinates.size(); ++i)
    out.push_back({Kind::coordinate, static_cast<int>(i), coordinates[i]});
  const auto& states = sim.state_names();
  for (size_t i = 0; i < states.size(); ++i)
    if (!states[i].empty()) out.push_back({Kind::state, static_cast<int>(i), states[i]});
  const auto& outputs = sim.output_names();
  for (size_t i = 0; i < outputs.size(); ++i)
    if (!outputs[i].empty() && sim.output_differentiated(static_cast<int>(i)))
      out.push_back({Kind::output, static_cast<int>(i), outputs[i]});
  return out;
}

double column_value(const Simulation& sim, const SensitivityColumn& c) {
  switch (c.kind) {
    case SensitivityColumn::Kind::coordinate:
      return sim.z()(c.index);
    case SensitivityColumn::Kind::state:
      return sim.states()(c.index);
    case SensitivityColumn::Kind::output:
      break;
  }
  return sim.outputs()(c.index);
}

double column_sensitivity(const Simulation& sim, const SensitivityColumn& c, int j) {
  switch (c.kind) {
    case SensitivityColumn::Kind::coordinate:
      return sim.coordinate_sensitivities()(c.index, j);
    case SensitivityColumn::Kind::state:
      return sim.state_sensitivities()(c.index, j);
    case SensitivityColumn::Kind::output:
      break;
  }
  return sim.output_sensitivities()(c.index, j);
}

std::vector<ParameterDirection> parameter_directions(const RunRequest& request,
                                                     const ModelFile& file,
                                                     const std::vector<std::string>& paths) {
  std::string text = read_model_text(request.model_path);
  std::string label = request.model_path;
  if (!request.overrides.set.empty())
    text = host::apply_settings(text, label, request.overrides.set).text;
  const std::string base = request.model_path.find('/') == std::string::npos
                               ? "."
                               : request.model_path.substr(0, request.model_path.rfind('/'));
  std::vector<ParameterDirection> directions;
  directions.reserve(paths.size());
  for (const std::string& path : paths)
    directions.push_back(host::parameter_direction(text, label, base, file, path));
  return directions;
}

}  // namespace mh::cli
