#include "variable_table.hpp"

#include <algorithm>

namespace mh::embed {

VariableTable::VariableTable(const Simulation& sim, const Model& model) {
  const auto& names = sim.coordinate_names();
  for (size_t i = 0; i < names.size(); ++i) {
    const bool angle = model.bodies[i].joint == JointType::revolute;
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
  add(MHS_STATE, sim.state_info());
  add(MHS_OUTPUT, sim.output_info());
  const std::vector<InputSpec>& inputs = sim.inputs();
  for (size_t k = 0; k < inputs.size(); ++k)
    variables_.push_back({MHS_INPUT, static_cast<int>(k), inputs[k].name,
                          "inputs." + inputs[k].name, inputs[k].unit, inputs[k].min,
                          inputs[k].max});
  for (size_t k = 0; k < variables_.size(); ++k) {
    by_name_.emplace(variables_[k].qualified, static_cast<int>(k));
    by_name_.emplace(variables_[k].name, static_cast<int>(k));
  }
}

int VariableTable::find(const std::string& name) const {
  const auto it = by_name_.find(name);
  return it == by_name_.end() ? -1 : it->second;
}

double value(const Simulation& sim, const Variable& v) {
  switch (v.kind) {
    case MHS_COORDINATE:
      return sim.z()[v.index];
    case MHS_COORDINATE_RATE:
      return sim.zd()[v.index];
    case MHS_STATE:
      return sim.states()[v.index];
    case MHS_INPUT:
      return sim.input(v.index);
    default:
      return sim.outputs()[v.index];
  }
}

}  // namespace mh::embed
