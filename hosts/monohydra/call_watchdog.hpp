// A time limit on every plugin call, so that a plugin that never returns (a
// loop in its create, a deadlock in its evaluate) cannot hang a command. A
// thread of the host watches the call the engine marks as in flight (core's
// plugin_call.hpp); when one call has not returned, and made no nested call,
// for the limit, it says which (the instance, its library, the call, the time
// and step) and ends the process with exit code 1. The CSV rows written
// before stay. Policy of the host, not of the engine: the core only marks.
#pragma once

namespace mh::cli {

// The limit when a command is not given one (s): far above any call of the
// shipped plugins (the longest, a formulation's setup, takes milliseconds).
constexpr double kDefaultCallTimeout = 60.0;

// Starts this process's watchdog with `seconds` (<= 0: none). Call again in
// a forked child: threads do not survive fork. A second call in the same
// process changes the limit. Watches the calls of the thread that calls it
// (the one that steps the run).
void start_call_watchdog(double seconds);

}  // namespace mh::cli
