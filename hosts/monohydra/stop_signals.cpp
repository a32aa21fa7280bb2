#include "stop_signals.hpp"

#include <signal.h>

#include <cstdio>

namespace mh::cli {
namespace {

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int signal) {
  g_stop = signal;
}

}  // namespace

const volatile std::sig_atomic_t* install_stop_handlers() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a write under way completes: no cut row
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    return true;
  }();
  (void)installed;
  return &g_stop;
}

int pending_stop_signal() {
  return static_cast<int>(g_stop);
}

const char* signal_name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  // The signals a crashing run dies from (isolated_run.hpp).
  if (signal == SIGSEGV) return "SIGSEGV";
  if (signal == SIGBUS) return "SIGBUS";
  if (signal == SIGABRT) return "SIGABRT";
  if (signal == SIGFPE) return "SIGFPE";
  if (signal == SIGILL) return "SIGILL";
  if (signal == SIGKILL) return "SIGKILL";
  static char buf[32];
  std::snprintf(buf, sizeof buf, "signal %d", signal);
  return buf;
}

}  // namespace mh::cli
