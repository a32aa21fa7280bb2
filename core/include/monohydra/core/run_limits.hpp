// What a run is checked against before it starts: a step count that fits
// (t_end / dt overflowed to zero steps before), a CSV that fits on a disk,
// and names that mean something. A run that breaks one never starts; the
// InputError says the numbers, the accepted range and the flag that moves it.
#pragma once

#include <cstddef>

#include "monohydra/core/model_file.hpp"

namespace mh {

class Simulation;

constexpr double kMinTimeStep = 1e-9;  // s; below it t_end / dt is noise, not a plan
constexpr double kCsvBytesPerCell = 20.0;

struct RunLimits {
  double max_steps = 1e8;          // --max-steps
  double max_output_bytes = 10e9;  // --max-output-bytes
};

// Which of dt and t_end the command line gave (its flag is named in messages
// instead of the model file's solver block).
struct SettingOrigins {
  bool dt_flag = false;
  bool t_end_flag = false;
};

// The steps of a run, round(t_end / dt), or -1 when that is not a number of
// steps from 1 to 2^53 (never overflows).
long planned_steps(const SolverSettings& settings);

// Checks dt, t_end and the output of a run of `settings` with `csv_columns`
// columns (0: no CSV), a row every `rows_every` steps (output.interval: only
// the rows written count), and returns its step count. Requires the model file to
// give solver.dt and solver.t_end unless the flags did: every model ends with
// its solver block, so a file cut short stops here. Throws InputError.
long check_run_settings(const ModelFile& file, const SolverSettings& settings,
                        const RunLimits& limits, std::size_t csv_columns,
                        SettingOrigins origins = {}, long rows_every = 1);

// Every key under a subsystem's states: and outputs: names a state or output
// the component declared. Throws InputError.
void check_column_names(const ModelFile& file, const Simulation& sim);

}  // namespace mh
