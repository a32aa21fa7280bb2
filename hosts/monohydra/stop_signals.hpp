// SIGINT and SIGTERM end a run cleanly: the handlers only set a flag (all a
// handler may safely do); the run loop checks it between steps, so the CSV
// ends on a whole row and the run says where it stopped.
#pragma once

#include <csignal>

namespace mh::cli {

// Installs the handlers (once) and returns the flag: 0, or the signal number.
const volatile std::sig_atomic_t* install_stop_handlers();

// The stop signal this process has received (0: none), for the call
// watchdog (call_watchdog.hpp), which ends a run whose plugin call does not
// return to let it stop.
int pending_stop_signal();

// "SIGINT", "SIGTERM", "SIGSEGV" and the other crashes, or "signal N".
const char* signal_name(int signal);

// The shell's convention for a process ended by `signal`: 128 + signal.
inline int exit_status_for_signal(int signal) {
  return 128 + signal;
}

}  // namespace mh::cli
