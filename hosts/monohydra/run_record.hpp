// One run of a model (a formulation under an integrator), kept in memory column by column with the
// same doubles its CSV holds: what the comparison table and the report are
// computed from.
#pragma once

#include <csignal>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run_limits.hpp"
#include "monohydra/core/simulation.hpp"
#include "step_overrides.hpp"

namespace mh::cli {

// The column the comparison adds after `monohydra run`'s columns: the wall time
// (s) spent computing the row, start() for t = 0 and the steps since the
// last row after that (one step, unless output.interval skips rows; writing
// the CSV is not counted).
inline constexpr const char* kWallColumn = "wall_s";

struct RunRecord {
  std::string label;  // what varies between the runs compared: F, I or "F+I"
  std::string formulation, integrator;
  bool failed = false;
  std::string failure;     // why, when failed: the setup error or "t = .. s, step ..: reason"
  std::string crash_site;  // a crash in a plugin call: " in <instance>, in its <call>, at t, step"
  std::optional<double> failure_time;  // s: the step that failed (none: setup failed)
  double dt = 0.0;                     // s, the settings the run used
  double t_end = 0.0;                  // s
  // Columns in CSV order: t, z1..zN, written states, written outputs, KE, PE,
  // W, drift, phi_norm, iters, wall_s; units parallel ("s", "rad" or "m" for
  // coordinates, as declared for states and outputs, "J" for energies).
  std::vector<std::string> names;
  std::vector<std::string> units;
  std::vector<VariableInfo> info;  // parallel: kinds, roles and ranges of states and outputs
  std::vector<std::vector<double>> columns;  // columns[c][row]
  int num_coordinates = 0;                   // z1..zN are columns 1..N
  int num_states = 0;                        // written states follow them
  std::string csv_path;                      // "" when no CSV was written
  int stopped_by = 0;           // the signal that stopped the run between two steps, 0 if none
  ExplicitStability stability;  // an explicit integrator's stability checks (checks = 0: none)
  int crashed_by = 0;  // the signal that killed the run's process (isolated_run.hpp), 0 if none
  // Where the subsystems' dissipation went: every subsystem instance (model
  // order) and the energy it dissipated (J) from t = 0 to the last step
  // taken, the trapezoidal integral per step of its power, as the core
  // integrates their sum (Simulation::dissipation_powers).
  std::vector<std::string> dissipators;
  std::vector<double> dissipated;
  // Where within an instance: the outputs its component gives the role
  // MH_ROLE_DISSIPATION_PART ("instance.output", W), each integrated the same
  // way; an instance's parts add up to its entry above.
  std::vector<std::string> dissipation_parts;
  std::vector<double> parts_dissipated;

  size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  int column(const std::string& name) const;  // -1 when absent
  // The column named `name`; throws std::out_of_range when absent.
  const std::vector<double>& values(const std::string& name) const;
};

struct RecordOptions {
  StepOverrides overrides;  // of the model file's solver settings (dt, t_end, limits)
  std::string csv_path;     // write the CSV here when not empty
  LogSink log;
  std::function<void(double)> progress;  // fraction done, about 100 calls
  // overrides.limits are checked before the first step; the CSV counts
  // towards max_output_bytes.
  // Non-zero (a signal number, see stop_signals.hpp): stop after the current row.
  const volatile std::sig_atomic_t* stop = nullptr;
  // Called with the record after each row it keeps (isolated_run.hpp streams
  // the rows to the parent process as they come).
  std::function<void(const RunRecord&)> on_row;
};

// Runs the model with the formulation and integrator `choices` name (dt and
// t_end from `options`) from t = 0 to t_end. Never throws for a run
// that fails: a formulation that cannot be set up gives a record with no rows,
// a step that fails stops the run and keeps the rows before it; both set
// `failed` and `failure`.
RunRecord record_run(const ModelFile& file, const PluginRegistry& registry,
                     const std::string& formulation, const std::string& integrator,
                     const RecordOptions& options);

}  // namespace mh::cli
