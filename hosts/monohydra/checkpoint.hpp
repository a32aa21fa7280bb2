// A run's checkpoint on disk (run --save-state FILE [--at T], run --resume
// FILE): the whole run state as the embedding API's snapshot bytes
// (run_state_bytes.hpp), so a resumed run continues bit for bit, and a
// file of another model, another build, cut short or changed is refused with
// the reason.
#pragma once

#include <string>

#include "monohydra/core/run_state.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh::cli {

// Writes the simulation's state to `path` (through a temporary file renamed
// over it: a reader never sees half a checkpoint). Throws SimulationError
// naming the file and why it could not be written.
void save_checkpoint(const Simulation& sim, const std::string& path);

// Reads a checkpoint into `into`. Throws RunStateError naming the file and
// what is wrong with it.
void load_checkpoint(const std::string& path, RunState& into);

}  // namespace mh::cli
