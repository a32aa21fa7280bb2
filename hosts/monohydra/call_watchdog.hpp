// A time limit on every plugin call, so that a plugin that never returns (a
// loop in its create, a deadlock in its evaluate) cannot hang a command. A
// thread of the host watches the call the engine marks as in flight (core's
// plugin_call.hpp); when one call has not returned, and made no nested call,
// for the limit, it says which (the instance, its library, the call, the time
// and step) and ends the process with exit code 1. The CSV rows written
// before stay. A stop signal (SIGINT, SIGTERM) is honoured between rows; one
// that arrives while a plugin call is in flight, which then does not return
// within a tick or two of the watchdog (at most 0.4 s), ends the process at
// once, naming the call, with the signal's exit status. Policy of the host,
// not of the engine: the core only marks.
#pragma once

namespace mh::cli {

// How long one plugin call may go without returning (or making a nested
// call) before the command is stopped, by the kind of call (s; 0: no limit).
// The defaults are far above what the shipped plugins take and far below a
// minute: a call of the set-up (create, setup, start, destroy) may read
// files and solve an initial state (the shipped ones take milliseconds); a
// call inside a step is one evaluation (microseconds). `--call-timeout S`
// sets both.
struct CallLimits {
  double setup = 30.0;
  double step = 5.0;
  static CallLimits uniform(double seconds) { return {seconds, seconds}; }
  // The limit of the call named `call` (a PluginCallSite's).
  double of(const char* call) const;
};

// Starts this process's watchdog with `limits` (both 0: none). Call again
// in a forked child: threads do not survive fork. A second call in the same
// process changes the limits. Watches the calls of the thread that calls it
// (the one that steps the run).
void start_call_watchdog(const CallLimits& limits = {});

}  // namespace mh::cli
