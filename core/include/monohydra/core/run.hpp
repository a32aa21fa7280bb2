// Running a simulation to its end time, writing one CSV row per accepted
// step. A failing step, a failed write or a stop request ends the run with its
// time, step and reason; every row written before it stays in the file, whole.
#pragma once

#include <csignal>
#include <functional>
#include <ostream>
#include <string>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {

// How a run ended; only `completed` reached t_end.
enum class RunEnd {
  completed,
  simulation_failed,  // a step failed (SimulationError)
  bad_input,          // the model or settings cannot run (InputError at start, no steps;
                      // a state to resume of another run, RunStateError)
  write_failed,       // the CSV could not be written: stopped at once
  interrupted,        // RunOptions::stop was set (a signal): stopped between two steps
};

struct RunSummary {
  long steps = 0;          // steps done (by this run: after the resumed state's)
  long first_step = 0;     // the step it started from: 0, or the resumed state's
  long steps_asked = 0;    // round(t_end / dt)
  long iterations = 0;     // Newton iterations, all steps
  int max_iterations = 0;  // in one step
  long retries = 0;        // halvings of failed steps (solver.max_step_halvings)
  long damped = 0;         // Newton increments the line search shortened
  long tangents = 0;       // tangents assembled and factored, all steps
  long rows = 0;           // CSV rows written (the header not counted)
  // Real-time mode only: steps whose result came after their wall-clock
  // deadline, by how much (s), and steps accepted before Newton converged.
  bool real_time = false;
  long deadlines_missed = 0;
  double max_late = 0.0, total_late = 0.0;
  long unconverged_steps = 0;
  double max_unconverged = 0.0;  // max_i |dx_i| / tol_i of the worst such step
  double max_abs_drift = 0.0;
  double max_phi_norm = 0.0;
  double wall_seconds = 0.0;
  double end_time = 0.0;  // s: the time of the last row (the last accepted state)
  RunEnd end = RunEnd::completed;
  int stop_signal = 0;  // the value *RunOptions::stop had when interrupted
  bool failed = false;  // end != completed
  std::string failure;  // why, when failed: SimulationError::what(), the write error, ...
};

struct RunOptions {
  // Called with the fraction done, at most ~100 times; may be empty.
  std::function<void(double)> progress;
  // When it points at a non-zero value (a signal handler's flag), the run stops
  // after the row of the current step: no CSV row is ever cut.
  const volatile std::sig_atomic_t* stop = nullptr;
  std::string csv_name;  // names the CSV in write errors
  // Flush the CSV after every row: a process that dies (a plugin's segfault)
  // keeps every row it computed. Costs one write per row.
  bool flush_rows = false;
  // The columns and interval of the rows; null: every column at every step.
  const CsvLayout* layout = nullptr;
  // Real-time mode: each step k -> k+1 starts no earlier than wall time
  // t_k after the start and is due at t_{k+1}; Newton stops at
  // `iteration_cap` iterations or that deadline and accepts the step as it
  // stands. Results then depend on the machine; every other run is
  // bit-identical from run to run. 0: off.
  int real_time_cap = 0;
  // A saved state to go on from (a checkpoint, run_state_bytes.hpp): restored
  // after start(), so the rows begin at its time and continue as the saved
  // run's would, bit for bit. Another model's state stops the run as bad input.
  const RunState* resume = nullptr;
  // Called between two steps: before each one (e.g. inputs set from outside,
  // Simulation::set_input) and after each one (e.g. a checkpoint at a time).
  // Either may throw SimulationError (the run stops with it, every row
  // before it kept) or InputError (bad input, before any step).
  std::function<void(Simulation&)> before_step;
  std::function<void(const Simulation&)> after_step;
};

// start()s the simulation and steps it to settings().t_end. `csv` may be null.
// Every write is checked: a failed one stops the run (RunEnd::write_failed).
RunSummary run(Simulation& sim, std::ostream* csv, const RunOptions& options);
RunSummary run(Simulation& sim, std::ostream* csv,
               const std::function<void(double)>& progress = nullptr);

}  // namespace mh
