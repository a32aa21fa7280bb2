// A crash inside a plugin call, told by the child that steps to the parent
// that reports it: the child's handler copies the call in flight (core's
// plugin_call.hpp: the instance, the call, the time and step) into a page
// both processes share, then dies of the same signal; the parent, seeing the
// signal, names them. Without a call in flight (a crash in the host's own
// code) the report is empty and the parent says so.
#pragma once

#include <csignal>
#include <string>

namespace mh::cli {

struct CrashReport {
  volatile std::sig_atomic_t signal = 0;
  long step = 0;
  double t = 0.0;
  char who[512] = {};
  char call[64] = {};
  // With no call in flight on the crashing thread (a thread a plugin
  // started): the file name of the library whose code crashed, if known.
  char code[256] = {};
};

// A zeroed report shared with children forked after it (nullptr if the
// system refuses the mapping: then crashes are reported without it).
CrashReport* shared_crash_report();

// Unmaps a report (nullptr: nothing).
void release_crash_report(CrashReport* report);

// In the child: SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT fill `report`
// before the process dies of them (on an alternate stack: a stack overflow
// is reported too). With no report (a process reporting for itself, as the
// CLI does for the calls it makes itself) the call in flight is said on stderr.
void install_crash_handler(CrashReport* report);

// In the parent: " in subsystem 'x' (type) of lib.so, in its evaluate, at
// t = 0.5 s, step 500"; " in the code of lib.so, outside the plugin calls
// the host marks (a thread it started)" when no call was in flight on the
// crashing thread but its instruction was in a plugin library; or "" when
// the report names neither.
std::string crash_site(const CrashReport* report);

}  // namespace mh::cli
