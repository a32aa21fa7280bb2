// Running a simulation to its end time, writing one CSV row per accepted
// step. A failing step stops the run with its time, step and reason; every row
// written before it stays in the file.
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "monohydra/core/simulation.hpp"

namespace mh {

// Columns: t, z1..zN, one per subsystem state and output (unless hidden), KE, PE,
// W, drift, phi_norm, iters.
void write_csv_header(std::ostream& out, const Simulation& sim);
void write_csv_row(std::ostream& out, const Simulation& sim);

struct RunSummary {
  long steps = 0;
  long iterations = 0;     // Newton iterations, all steps
  int max_iterations = 0;  // in one step
  double max_abs_drift = 0.0;
  double max_phi_norm = 0.0;
  double wall_seconds = 0.0;
  bool failed = false;
  std::string failure;  // SimulationError::what() when failed
};

// start()s the simulation and steps it to settings().t_end. `csv` may be null.
// `progress` (may be empty) is called with the fraction done, at most ~100 times.
RunSummary run(Simulation& sim, std::ostream* csv,
               const std::function<void(double)>& progress = nullptr);

}  // namespace mh
