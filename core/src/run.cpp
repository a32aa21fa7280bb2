#include "monohydra/core/run.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "monohydra/core/run_limits.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh {
// Messages short.
using monohydra::short_number;

namespace {
class CsvWriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A row goes out in one write so that a stop never leaves half of it; a
// failed write (disk full, /dev/full) is reported at once with errno's reason.
void write_checked(std::ostream& out, const std::string& text, const std::string& name,
                   bool flush = false) {
  errno = 0;
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (flush) out.flush();
  if (!out) {
    const int err = errno;
    throw CsvWriteError("cannot write the results to '" + name +
                        "': " + (err != 0 ? std::strerror(err) : "write failed"));
  }
}

std::string where(const RunSummary& s) {
  return "t = " + short_number(s.end_time) + " s, step " + std::to_string(s.first_step + s.steps) +
         " of " + std::to_string(s.steps_asked);
}
}  // namespace

RunSummary run(Simulation& sim, std::ostream* csv, const std::function<void(double)>& progress) {
  RunOptions options;
  options.progress = progress;
  return run(sim, csv, options);
}

RunSummary run(Simulation& sim, std::ostream* csv, const RunOptions& options) {
  RunSummary summary;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string csv_name = options.csv_name.empty() ? "the CSV" : options.csv_name;
  std::ostringstream line;
  const bool real_time = options.real_time_cap > 0;
  summary.real_time = real_time;
  std::optional<CsvLayout> all_columns;
  const CsvLayout* layout = options.layout;
  RealTimeRow rt;
  const auto write_row = [&] {
    if (csv == nullptr) return;
    line.str("");
    layout->row(line, sim, rt);
    write_checked(*csv, line.str(), csv_name);
    ++summary.rows;
    if (options.flush_rows) write_checked(*csv, "", csv_name, true);
  };
  const auto stopped = [&] { return options.stop != nullptr && *options.stop != 0; };
  try {
    summary.steps_asked = planned_steps(sim.settings());
    if (summary.steps_asked < 0)
      throw InputError(sim.settings().mark, "solver",
                       "t_end / dt = " + short_number(sim.settings().t_end) + " / " +
                           short_number(sim.settings().dt) +
                           " is not a number of steps from 1 to 2^53");
    if (layout == nullptr) layout = &all_columns.emplace(sim, real_time);
    const long every = layout->every_steps();
    sim.set_real_time(options.real_time_cap);
    sim.start();
    if (options.resume != nullptr) sim.restore_state(*options.resume);
    const long first = sim.step_index();  // 0, or the resumed state's step
    summary.first_step = first;
    summary.end_time = sim.time();
    if (csv != nullptr) {
      line.str("");
      layout->header(line);
      write_checked(*csv, line.str(), csv_name);
    }
    write_row();
    const long total = summary.steps_asked;
    const long report_every = std::max(1L, total / 100);
    const double dt = sim.settings().dt;
    const auto wall0 = std::chrono::steady_clock::now();
    const auto wall_at = [&](long k) {  // wall time at which simulated t_k is due
      return wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                         std::chrono::duration<double>(static_cast<double>(k - first) * dt));
    };
    for (long k = first; k < total && !stopped(); ++k) {
      if (options.before_step) options.before_step(sim);
      std::chrono::steady_clock::time_point deadline{};
      if (real_time) {  // pacing: never ahead of the wall clock
        std::this_thread::sleep_until(wall_at(k));
        deadline = wall_at(k + 1);
        sim.set_step_deadline(deadline);
      }
      sim.step();
      ++summary.steps;
      summary.tangents += sim.last_step().tangents;
      if (real_time) {
        rt.late = std::max(
            0.0,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - deadline).count());
        rt.unconverged = sim.last_step().converged ? 0.0 : sim.last_step().unconverged;
        if (rt.late > 0.0) {
          ++summary.deadlines_missed;
          summary.total_late += rt.late;
          summary.max_late = std::max(summary.max_late, rt.late);
        }
        if (!sim.last_step().converged) {
          ++summary.unconverged_steps;
          summary.max_unconverged = std::max(summary.max_unconverged, rt.unconverged);
        }
      }
      summary.end_time = sim.time();
      const int it = sim.last_step().iterations;
      summary.iterations += it;
      summary.max_iterations = std::max(summary.max_iterations, it);
      summary.retries += sim.last_step().retries;
      summary.damped += sim.last_step().damped;
      summary.max_abs_drift = std::max(summary.max_abs_drift, std::abs(sim.drift()));
      summary.max_phi_norm = std::max(summary.max_phi_norm, sim.phi_norm());
      if ((k + 1) % every == 0) write_row();
      if (options.after_step) options.after_step(sim);
      if (options.progress && (k + 1) % report_every == 0)
        options.progress(static_cast<double>(k + 1) / static_cast<double>(total));
    }
    if (csv != nullptr) {
      errno = 0;
      csv->flush();
      if (!*csv)
        throw CsvWriteError("cannot write the results to '" + csv_name +
                            "': " + (errno != 0 ? std::strerror(errno) : "write failed"));
    }
    if (first + summary.steps < total) {
      summary.end = RunEnd::interrupted;
      summary.stop_signal = static_cast<int>(*options.stop);
      summary.failure = "stopped at " + where(summary);
    }
  } catch (const SimulationError& err) {
    summary.end = RunEnd::simulation_failed;
    summary.failure = err.what();
  } catch (const InputError& err) {  // e.g. an unknown state under equilibrium.free
    summary.end = RunEnd::bad_input;
    summary.failure = err.what();
  } catch (const RunStateError& err) {  // a state to resume that is another run's
    summary.end = RunEnd::bad_input;
    summary.failure = std::string("cannot resume: ") + err.what();
  } catch (const CsvWriteError& err) {
    summary.end = RunEnd::write_failed;
    summary.failure = "stopped at " + where(summary) + ": " + err.what();
  }
  summary.failed = summary.end != RunEnd::completed;
  if (csv != nullptr && summary.end != RunEnd::write_failed) csv->flush();
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace mh
