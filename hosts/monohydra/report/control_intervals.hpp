// When a control signal is on, to shade those intervals in the report's time
// plots as the paper shades the intervals in which its control input is on
// (Sect. 6.1). Which
// columns are control signals, and their scale, is what their components
// declared (role MH_ROLE_CONTROL_SIGNAL with a range): a signal is on while
// its magnitude exceeds 1 % of max(|range_min|, |range_max|).
#pragma once

#include <string>
#include <vector>

#include "run_record.hpp"
#include "svg_plot.hpp"

namespace mh::cli {

inline constexpr double kControlOnFraction = 0.01;

struct ControlColumn {
  std::string name;  // the result column
  double threshold;  // |value| above it: on
};

// The run's columns with the control-signal role and a range, in column order.
std::vector<ControlColumn> control_columns(const RunRecord& run);

// The intervals [t_first, t_last] of consecutive rows in which any of the
// columns is on; merged, in time order.
std::vector<PlotInterval> control_on_intervals(const RunRecord& run,
                                               const std::vector<ControlColumn>& columns);

}  // namespace mh::cli
