// The comparison table's numbers, computed from a run's columns (the same
// doubles as its CSV). Definitions: docs/compare.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "run_record.hpp"

namespace mh::cli {

struct RunMetrics {
  long steps = 0;                  // rows after t = 0
  double simulated_seconds = 0.0;  // t of the last row
  double avg_iterations = 0.0;     // mean of iters over the steps
  int max_iterations = 0;          // max of iters over the steps
  double wall_seconds = 0.0;       // sum of wall_s over every row: start() and every step()
  double seconds_per_step = 0.0;   // sum of wall_s over the steps / steps
  // The costliest step: a row's wall_s over the steps it stands for (one when
  // every step is written), the largest over the rows, and the row's t.
  double worst_step_seconds = 0.0;
  double worst_step_time = 0.0;
  double real_time_factor = 0.0;  // simulated_seconds / wall_seconds (> 1: faster than real time)
  double peak_abs_drift = 0.0;    // max |drift| over every row (J)
  double peak_drift_time = 0.0;   // t of that row (s)
  double max_abs_work = 0.0;      // max |W| over every row (J): the maximum actuator work
  std::optional<double> drift_percent;  // peak_abs_drift / max_abs_work * 100; none when W is 0
  double max_phi_norm = 0.0;            // max phi_norm over every row
};

// Zeros for a run without rows.
RunMetrics compute_metrics(const RunRecord& run);

// The written states whose unit is "Pa": the pressures, in column order.
std::vector<std::string> pressure_columns(const RunRecord& run);

// How far a run is from the reference run, over the rows both have (the same
// times: both use the model's dt).
struct Differences {
  long rows = 0;                                 // rows compared
  std::optional<double> max_abs_z;               // max over rows and coordinates (rad or m)
  std::vector<std::optional<double>> pressures;  // max |p - p_ref| (Pa), one per name asked
};

// Throws std::invalid_argument when the two runs' times differ on a common row.
Differences differences(const RunRecord& run, const RunRecord& reference,
                        const std::vector<std::string>& pressure_names);

}  // namespace mh::cli
