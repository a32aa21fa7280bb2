#include "valve_intervals.hpp"

#include <cmath>

namespace mh::cli {

std::vector<std::string> valve_columns(const ModelFile& file) {
  std::vector<std::string> out;
  for (const SubsystemSpec& s : file.subsystems) {
    if (s.type != kValveType) continue;
    const auto named = s.state_names.find(kValveSpoolState);
    const std::string column =
        named != s.state_names.end() ? named->second : s.name + "." + kValveSpoolState;
    if (!column.empty()) out.push_back(column);
  }
  return out;
}

std::vector<PlotInterval> valve_open_intervals(const RunRecord& run,
                                               const std::vector<std::string>& columns) {
  std::vector<PlotInterval> out;
  std::vector<const std::vector<double>*> spools;
  for (const auto& c : columns)
    if (run.column(c) >= 0) spools.push_back(&run.values(c));
  if (spools.empty() || run.rows() == 0) return out;
  const auto& t = run.values("t");
  const double threshold = kValveOpenFraction * kValveFullScale;
  bool open = false;
  for (size_t k = 0; k < run.rows(); ++k) {
    bool now = false;
    for (const auto* u : spools) now = now || std::abs((*u)[k]) > threshold;
    if (now && !open) out.push_back({t[k], t[k]});
    if (now) out.back().end = t[k];
    open = now;
  }
  return out;
}

}  // namespace mh::cli
