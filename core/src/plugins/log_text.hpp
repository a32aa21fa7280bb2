// A plugin's log line as the host passes it on: at most kLogTextLimit bytes
// of it, with what was cut counted, and every control character and byte
// that is not UTF-8 escaped, so that no plugin can flood a terminal or a
// log file, move its cursor or forge a line of the host's own.
#pragma once

#include <cstddef>
#include <string>

namespace mh {

inline constexpr std::size_t kLogTextLimit = 4096;

// NULL: "". Escapes: \n, \r, \t, \\ and \xHH; a line longer than the limit
// ends "... (N more bytes)".
std::string log_text(const char* message);

}  // namespace mh
