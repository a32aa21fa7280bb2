// A run's state (run_state.hpp) as a byte string, to be kept in a file or
// sent to another process of the same build and restored there: the
// embedding API's snapshots to bytes and the command line's checkpoints.
// The bytes carry a format version, this build's layout of the host's
// structs and a checksum, so that bytes of another build, cut short or
// changed are refused with the reason instead of restored as garbage.
#pragma once

#include <cstddef>
#include <vector>

#include "monohydra/core/run_state.hpp"

namespace mh {

// Writes `state` into `out` (resized; its storage reused when large enough).
void write_run_state_bytes(const RunState& state, std::vector<unsigned char>& out);

// Reads bytes written by write_run_state_bytes into `into`. Throws
// RunStateError naming what is wrong (not a monohydra state, another format
// version or build, cut short, a checksum that does not match, a length out
// of range); `into` is then unspecified, the bytes are not restored.
void read_run_state_bytes(const unsigned char* data, std::size_t size, RunState& into);

}  // namespace mh
