// The one supervisor of the commands that run plugin code in their own
// process (validate, linearize, sensitivities, fit, estimate, forces, fmu): the
// command runs in a forked child under the crash handler and the call
// watchdog, and this process waits for it, passing SIGINT and SIGTERM on. A
// plugin that crashes, aborts, traps or overflows its stack then ends the
// child, not the command, which names the signal and the plugin call in
// flight (crash_report.hpp) and exits 1; output the command wrote before
// stays. `run` and `compare` step their runs in children of their own
// (commands.cpp, isolated_run.cpp) and `check` each of its checks.
#pragma once

#include <functional>

namespace mh::cli {

// `body`'s exit code, from a child; 1 when the child died of a crash, 128 +
// the signal when SIGINT or SIGTERM ended it. Without fork, `body` here.
int supervised(const std::function<int()>& body);

}  // namespace mh::cli
