// monohydra SDK, optional C++17 helper (header-only): numbers as text, one
// way each for the host and its plugins, so that a value reads the same in
// a plugin's log line, the host's message and the results.
#pragma once

#include <charconv>
#include <cstdio>
#include <ostream>
#include <string>

namespace monohydra {

// For messages and logs: 6 significant digits (printf's %.6g), enough to
// compare a value with a limit at a glance.
inline std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// For results: the shortest text that reads back as the same double
// (std::to_chars), written at `first` (32 characters are always enough).
// Returns the end of what it wrote. Allocates nothing: fit for every row.
inline char* write_exact_number(char* first, double v) {
  return std::to_chars(first, first + 32, v).ptr;
}

inline void put_exact_number(std::ostream& out, double v) {
  char buf[32];
  out.write(buf, write_exact_number(buf, v) - buf);
}

inline std::string exact_number(double v) {
  char buf[32];
  return std::string(buf, write_exact_number(buf, v));
}

}  // namespace monohydra
