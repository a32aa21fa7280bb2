#include "control_intervals.hpp"

#include <algorithm>
#include <cmath>

#include "monohydra/host.h"

namespace mh::cli {

std::vector<ControlColumn> control_columns(const RunRecord& run) {
  std::vector<ControlColumn> out;
  for (size_t c = 0; c < run.info.size(); ++c) {
    const VariableInfo& v = run.info[c];
    const double scale = std::max(std::abs(v.range_min), std::abs(v.range_max));
    if (v.role == MH_ROLE_CONTROL_SIGNAL && scale > 0.0)
      out.push_back({run.names[c], kControlOnFraction * scale});
  }
  return out;
}

std::vector<PlotInterval> control_on_intervals(const RunRecord& run,
                                               const std::vector<ControlColumn>& columns) {
  std::vector<PlotInterval> out;
  std::vector<std::pair<const std::vector<double>*, double>> signals;
  for (const auto& c : columns)
    if (run.column(c.name) >= 0) signals.emplace_back(&run.values(c.name), c.threshold);
  if (signals.empty() || run.rows() == 0) return out;
  const auto& t = run.values("t");
  bool on = false;
  for (size_t k = 0; k < run.rows(); ++k) {
    bool now = false;
    for (const auto& [u, threshold] : signals) now = now || std::abs((*u)[k]) > threshold;
    if (now && !on) out.push_back({t[k], t[k]});
    if (now) out.back().end = t[k];
    on = now;
  }
  return out;
}

}  // namespace mh::cli
