#include "run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mh::cli {

RunMetrics compute_metrics(const RunRecord& run) {
  RunMetrics m;
  const size_t rows = run.rows();
  if (rows == 0) return m;
  const auto& t = run.values("t");
  const auto& iters = run.values("iters");
  const auto& wall = run.values(kWallColumn);
  const auto& drift = run.values("drift");
  const auto& work = run.values("W");
  const auto& phi = run.values("phi_norm");
  // Rows are every step, or every output.interval: the steps from the time.
  m.steps = run.dt > 0.0 ? std::lround(t.back() / run.dt) : static_cast<long>(rows) - 1;
  m.simulated_seconds = t.back();
  double iteration_sum = 0.0;
  double step_wall = 0.0;
  for (size_t k = 1; k < rows; ++k) {
    iteration_sum += iters[k];
    m.max_iterations = std::max(m.max_iterations, static_cast<int>(iters[k]));
    step_wall += wall[k];
    const double steps_in_row =
        run.dt > 0.0 ? std::max(1.0, std::round((t[k] - t[k - 1]) / run.dt)) : 1.0;
    if (wall[k] / steps_in_row > m.worst_step_seconds) {
      m.worst_step_seconds = wall[k] / steps_in_row;
      m.worst_step_time = t[k];
    }
  }
  m.wall_seconds = wall[0] + step_wall;
  if (m.steps > 0) {
    m.avg_iterations = iteration_sum / static_cast<double>(rows - 1);  // over the rows kept
    m.seconds_per_step = step_wall / static_cast<double>(m.steps);
  }
  if (m.wall_seconds > 0.0) m.real_time_factor = m.simulated_seconds / m.wall_seconds;
  for (size_t k = 0; k < rows; ++k) {
    if (std::abs(drift[k]) > m.peak_abs_drift) {
      m.peak_abs_drift = std::abs(drift[k]);
      m.peak_drift_time = t[k];
    }
    m.max_abs_work = std::max(m.max_abs_work, std::abs(work[k]));
    m.max_phi_norm = std::max(m.max_phi_norm, phi[k]);
  }
  if (m.max_abs_work > 0.0) m.drift_percent = m.peak_abs_drift / m.max_abs_work * 100.0;
  return m;
}

std::vector<std::string> pressure_columns(const RunRecord& run) {
  std::vector<std::string> out;
  const size_t first = 1 + static_cast<size_t>(run.num_coordinates);
  for (size_t c = first; c < first + static_cast<size_t>(run.num_states); ++c)
    if (run.units[c] == "Pa") out.push_back(run.names[c]);
  return out;
}

Differences differences(const RunRecord& run, const RunRecord& reference,
                        const std::vector<std::string>& pressure_names) {
  Differences d;
  const size_t rows = std::min(run.rows(), reference.rows());
  d.rows = static_cast<long>(rows);
  d.pressures.assign(pressure_names.size(), std::nullopt);
  if (rows == 0) return d;
  const auto& t = run.values("t");
  const auto& t_ref = reference.values("t");
  for (size_t k = 0; k < rows; ++k)
    if (std::abs(t[k] - t_ref[k]) > 1e-9 * std::max(1.0, std::abs(t_ref[k])))
      throw std::invalid_argument("the runs " + run.label + " and " + reference.label +
                                  " are not at the same times (row " + std::to_string(k) + ")");
  auto max_difference = [rows](const std::vector<double>& a, const std::vector<double>& b) {
    double m = 0.0;
    for (size_t k = 0; k < rows; ++k) m = std::max(m, std::abs(a[k] - b[k]));
    return m;
  };
  double dz = 0.0;
  for (int j = 1; j <= run.num_coordinates; ++j)
    dz = std::max(dz, max_difference(run.columns[static_cast<size_t>(j)],
                                     reference.columns[static_cast<size_t>(j)]));
  d.max_abs_z = dz;
  for (size_t i = 0; i < pressure_names.size(); ++i)
    if (run.column(pressure_names[i]) >= 0 && reference.column(pressure_names[i]) >= 0)
      d.pressures[i] =
          max_difference(run.values(pressure_names[i]), reference.values(pressure_names[i]));
  return d;
}

}  // namespace mh::cli
