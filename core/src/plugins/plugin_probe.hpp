// A library is opened first in a forked child: a plugin that crashes or hangs
// in dlopen, init or its factories takes the child down, not the host, as
// audio hosts scan their plugins out of process.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace mh {

// What the host reads of a library, bounded; the probe reads as far first,
// so that a library that lies about it crashes the probe, not the host.
inline constexpr uint32_t kMaxComponents = 10000;            // per factory's count()
inline constexpr size_t kMaxMeasuredText = size_t{1} << 26;  // strnlen of a descriptor text

struct ProbeVerdict {
  bool usable = true;  // the child exited 0: the host may load it itself
  std::string reason;  // when not: "crashed with SIGSEGV during probing", ...
};

// Forks; the child dlopens `path`, checks the entry, calls init, lists every
// factory's components (count bounded) and deinit, then _exits 0. A library
// that is not a plugin still exits 0: the host's own load names what is wrong.
// The parent kills the child (SIGKILL) after `limit`.
ProbeVerdict probe_library(const std::string& path, std::chrono::milliseconds limit);

// "SIGSEGV", "SIGBUS", ... or "signal 42".
std::string signal_abbreviation(int sig);

}  // namespace mh
