#include "comparison.hpp"

#include <utility>

namespace mh::cli {

bool Comparison::any_failed() const {
  for (const auto& r : runs)
    if (r.failed) return true;
  return false;
}

Comparison summarize(std::string name, std::string model_path, std::vector<RunRecord> runs) {
  Comparison c;
  c.name = std::move(name);
  c.model_path = std::move(model_path);
  c.runs = std::move(runs);
  for (size_t i = 0; i < c.runs.size(); ++i) {
    c.metrics.push_back(compute_metrics(c.runs[i]));
    if (c.reference < 0 && c.runs[i].rows() > 0) c.reference = static_cast<int>(i);
  }
  c.differences.assign(c.runs.size(), std::nullopt);
  if (const RunRecord* ref = c.reference_run()) {
    c.pressures = pressure_columns(*ref);
    for (size_t i = 0; i < c.runs.size(); ++i)
      if (c.runs[i].rows() > 0) c.differences[i] = differences(c.runs[i], *ref, c.pressures);
  }
  return c;
}

}  // namespace mh::cli
