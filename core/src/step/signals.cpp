#include "step/signals.hpp"

namespace mh {

void Signals::make_inputs(const std::vector<InputSpec>& specs, RunData& run) {
  inputs.clear();
  run.input_values.clear();
  run.input_follows_table.clear();
  for (const InputSpec& spec : specs) {
    InputSignal in;
    in.spec = &spec;
    std::string error;
    if (!spec.table.empty())
      in.table.assign(spec.table.data(), static_cast<uint32_t>(spec.table.size() / 2), error);
    inputs.push_back(std::move(in));
    run.input_follows_table.push_back(spec.table.empty() ? 0 : 1);
    run.input_values.push_back(spec.initial);
  }
}

int Signals::find_input(const std::string& name) const {
  for (size_t k = 0; k < inputs.size(); ++k)
    if (inputs[k].spec->name == name) return static_cast<int>(k);
  return -1;
}

}  // namespace mh
