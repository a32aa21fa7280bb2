// Checks a run's settings before it starts (run_limits.hpp): every number
// that reaches the step loop is finite, sized and said back in the message.
#include "monohydra/core/run_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "monohydra/core/simulation.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh {
namespace {

using monohydra::short_number;

// Where a setting came from: its line in the model file, or its flag.
struct Origin {
  SourceMark mark;
  std::string field;
};

Origin origin(const ModelFile& file, const SourceMark& written, bool flag, const char* flag_name,
              const char* key) {
  if (flag) return {SourceMark{"command line", 0, 0}, flag_name};
  SourceMark m = written.line > 0 ? written : file.solver.mark;
  if (m.file.empty()) m.file = file.path;
  return {m, std::string("solver.") + key};
}

}  // namespace

long planned_steps(const SolverSettings& settings) {
  const double n = std::round(settings.t_end / settings.dt);
  if (!(n >= 1.0 && n <= 9007199254740992.0)) return -1;  // NaN, inf, 0 or beyond 2^53
  return static_cast<long>(n);
}

long check_run_settings(const ModelFile& file, const SolverSettings& settings,
                        const RunLimits& limits, std::size_t csv_columns, SettingOrigins origins,
                        long rows_every) {
  const Origin dt = origin(file, file.solver.dt_mark, origins.dt_flag, "--dt", "dt");
  const Origin t_end = origin(file, file.solver.t_end_mark, origins.t_end_flag, "--t-end", "t_end");
  const auto require_written = [&](const Origin& o, bool flag, const SourceMark& written) {
    if (flag || written.line > 0) return;
    throw InputError(o.mark, o.field,
                     "missing: a run needs solver: {dt: S, t_end: S} in the model file (or --dt "
                     "and --t-end); every model ends with its solver block, so a file without "
                     "one may have been cut short");
  };
  require_written(dt, origins.dt_flag, file.solver.dt_mark);
  require_written(t_end, origins.t_end_flag, file.solver.t_end_mark);
  const double h = settings.dt;
  const double T = settings.t_end;
  if (!std::isfinite(T) || !(T > 0.0))
    throw InputError(t_end.mark, t_end.field,
                     "expected a positive finite end time in s (a run of zero steps is an "
                     "error), got " +
                         short_number(T));
  if (!std::isfinite(h) || !(h >= kMinTimeStep) || !(h <= T))
    throw InputError(dt.mark, dt.field,
                     "expected a time step from " + short_number(kMinTimeStep) +
                         " s to t_end = " + short_number(T) + " s, got " + short_number(h));
  const double steps = std::round(T / h);
  if (!(steps <= limits.max_steps) || planned_steps(settings) < 0)
    throw InputError(t_end.mark, t_end.field,
                     "t_end / dt = " + short_number(T) + " / " + short_number(h) + " = " +
                         short_number(steps) + " steps, above the limit of " +
                         short_number(limits.max_steps) + " steps (raise it with --max-steps N)");
  if (csv_columns > 0) {
    const double rows = std::floor(steps / static_cast<double>(std::max(1L, rows_every))) + 1.0;
    const double bytes = rows * static_cast<double>(csv_columns) * kCsvBytesPerCell;
    if (!(bytes <= limits.max_output_bytes))
      throw InputError(t_end.mark, t_end.field,
                       "the CSV would take about " + short_number(bytes) + " bytes (" +
                           short_number(rows) + " rows x " + std::to_string(csv_columns) +
                           " columns x ~" + short_number(kCsvBytesPerCell) +
                           " bytes), above the limit of " + short_number(limits.max_output_bytes) +
                           " bytes (raise it with --max-output-bytes N)");
  }
  return planned_steps(settings);
}

void check_column_names(const ModelFile& file, const Simulation& sim) {
  for (std::size_t i = 0; i < file.subsystems.size(); ++i) {
    const SubsystemSpec& spec = file.subsystems[i];
    const std::string field = "subsystems[" + std::to_string(i) + "].";
    const auto check = [&](const std::map<std::string, std::string>& names, const char* what,
                           bool states) {
      for (const auto& entry : names) {
        const std::string qualified = spec.name + "." + entry.first;
        const int found = states ? sim.state_index(qualified) : sim.output_index(qualified);
        if (found >= 0) continue;
        const auto written = spec.column_marks.find(std::string(what) + "s." + entry.first);
        const SourceMark& m = written != spec.column_marks.end() ? written->second : spec.mark;
        throw InputError(m, field + what + "s." + entry.first,
                         "unknown " + std::string(what) + " '" + entry.first + "' (the " +
                             spec.type + " '" + spec.name + "' declares no such " + what + ")");
      }
    };
    check(spec.state_names, "state", true);
    check(spec.output_names, "output", false);
  }
}

}  // namespace mh
