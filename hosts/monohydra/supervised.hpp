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

#include <sys/types.h>

#include <csignal>
#include <functional>

namespace mh::cli {

// Waits for the child `pid`, passing the stop signal `*stop` on to it once
// it is set; its wait status into `status`. False when waitpid fails.
bool wait_passing_stop(pid_t pid, const volatile std::sig_atomic_t* stop, int& status);

// `body`'s exit code, from a child; 1 when the child died of a crash, 128 +
// the signal when SIGINT or SIGTERM ended it. Without fork, `body` here.
int supervised(const std::function<int()>& body);

}  // namespace mh::cli
