// Everything a run needs, loaded and checked before its first step: the model,
// its plugins, the simulation set up, the result column names and the run's
// size (steps, CSV bytes). `run` and `validate` share it, so validate refuses
// exactly what run would.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "call_watchdog.hpp"
#include "model_plugins.hpp"
#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run_limits.hpp"
#include "monohydra/core/simulation.hpp"
#include "step_overrides.hpp"

namespace mh::cli {

struct RunRequest {
  std::string model_path;
  std::string formulation;                // "" for the model file's
  std::string integrator;                 // "" for the model file's
  StepOverrides overrides;                // --dt, --t-end, the limits, --explicit-stability
  bool csv = false;                       // the run writes a CSV (counted in the output limit)
  std::optional<double> output_interval;  // --output-interval: overrides output.interval
  int real_time_cap = 0;                  // --real-time: Newton iterations per step (0: off)
  CallLimits call_limits;                 // --call-timeout: s a plugin call may take (0: no limit)
  std::string save_state;                 // --save-state FILE: a checkpoint ("" none)
  std::optional<double> save_at;          // --at T: when (s; none: at the run's end)
  std::string resume;                     // --resume FILE: go on from a checkpoint
  std::string inputs;                     // --inputs FILE.csv, or "-": standard input
  bool stream = false;                    // --stream: rows to standard output as computed
  std::string report_dir;                 // --report DIR: the run's report.html and CSV there
  std::string sensors_out;                // --sensors-out FILE.csv: what the sensors read
  std::uint64_t seed = 1;                 // --seed N: the sensors' noise
};

struct PreparedRun {
  ModelFile file;
  PluginRegistry registry;
  std::unique_ptr<Simulation> sim;        // refers to file and registry: keep them together
  std::unique_ptr<CsvLayout> layout;      // the rows' columns and interval (output:)
  long steps = 0;                         // the steps the run will ask for
  std::size_t columns = 0;                // of the CSV
  std::vector<host::UsedComponent> used;  // the libraries its components come from
};

// The prepared run, or null after telling the user why on stderr.
std::unique_ptr<PreparedRun> prepare_run(const RunRequest& request);

}  // namespace mh::cli
