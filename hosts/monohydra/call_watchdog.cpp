// The watchdog of call_watchdog.hpp: a detached thread that samples the
// in-flight record every 200 ms (few wakeups: under a profiler they count) and
// needs no lock of the engine's.
#include "call_watchdog.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <thread>

#include "monohydra/core/plugin_call.hpp"
#include "stop_signals.hpp"

namespace mh::cli {
namespace {

std::atomic<double> g_setup_limit{0.0}, g_step_limit{0.0};
// The record of the thread that steps the run (the one that started the
// watchdog): a thread's own record is its thread_local (plugin_call.hpp).
std::atomic<const PluginCallInFlight*> g_record{nullptr};
std::atomic<pid_t> g_watched_pid{0};  // the process whose thread is running
std::atomic<pid_t> g_running_pid{0};  // the process whose thread has entered watch()

// `n` characters of `message` as snprintf made them (cut to the buffer) on
// stderr, with write(): the stepping thread may hold the stream's lock.
template <size_t Size>
void write_message(const char (&message)[Size], int n) {
  if (n <= 0) return;
  const size_t len = static_cast<size_t>(n) < Size ? static_cast<size_t>(n) : Size - 1;
  const ssize_t written = ::write(STDERR_FILENO, message, len);
  (void)written;
}

[[noreturn]] void stop_hung(const PluginCallSite& site, double seconds) {
  const PluginCallInFlight& record = *g_record.load(std::memory_order_relaxed);
  char message[1024];
  const int n = std::snprintf(
      message, sizeof message,
      "monohydra: %s has not returned from its %s within %g s (at t = %g s, step %ld): "
      "stopped (--call-timeout S raises the limit)\n",
      site.who != nullptr ? site.who : "a plugin", site.call != nullptr ? site.call : "call",
      seconds, record.t.load(std::memory_order_relaxed),
      record.step.load(std::memory_order_relaxed));
  write_message(message, n);
  std::_Exit(1);  // the hung call holds the engine: nothing else can run safely
}

// A stop signal arrived while `site` was in flight, and the call has not
// returned: the run cannot reach its next row to stop there.
[[noreturn]] void stop_interrupted(const PluginCallSite& site, int signal) {
  const PluginCallInFlight& record = *g_record.load(std::memory_order_relaxed);
  char message[1024];
  const int n = std::snprintf(
      message, sizeof message,
      "monohydra: interrupted by %s: %s had not returned from its %s (at t = %g s, step %ld): "
      "stopped there\n",
      signal_name(signal), site.who != nullptr ? site.who : "a plugin",
      site.call != nullptr ? site.call : "call", record.t.load(std::memory_order_relaxed),
      record.step.load(std::memory_order_relaxed));
  write_message(message, n);
  std::_Exit(exit_status_for_signal(signal));
}

void watch() {
  constexpr auto kPeriod = std::chrono::milliseconds(200);
  const PluginCallSite* last_site = nullptr;
  unsigned long last_entered = 0;
  double stuck = 0.0;
  bool stop_seen = false;  // a stop signal was pending during this call at the last tick
  g_running_pid.store(::getpid(), std::memory_order_release);
  for (;;) {
    std::this_thread::sleep_for(kPeriod);
    const PluginCallInFlight* watched = g_record.load(std::memory_order_relaxed);
    if (watched == nullptr) continue;
    const PluginCallInFlight& record = *watched;
    const PluginCallSite* site = record.site.load(std::memory_order_relaxed);
    const unsigned long entered = record.entered.load(std::memory_order_relaxed);
    const CallLimits limits{g_setup_limit.load(std::memory_order_relaxed),
                            g_step_limit.load(std::memory_order_relaxed)};
    const double limit = site != nullptr ? limits.of(site->call) : 0.0;
    const bool same_call = site != nullptr && site == last_site && entered == last_entered;
    // Stopped while this call, in flight at the last tick too, has not returned.
    const int signal = pending_stop_signal();
    if (same_call && signal != 0) {
      if (stop_seen) stop_interrupted(*site, signal);
      stop_seen = true;
    } else {
      stop_seen = false;
    }
    if (!same_call || !(limit > 0.0)) {
      last_site = site;
      last_entered = entered;
      stuck = 0.0;
      continue;
    }
    stuck += std::chrono::duration<double>(kPeriod).count();
    if (stuck >= limit) stop_hung(*site, limit);
  }
}

}  // namespace

double CallLimits::of(const char* call) const {
  if (call == nullptr) return step;
  for (const char* kind : {"create", "setup", "start", "destroy"})
    if (std::strcmp(call, kind) == 0) return setup;
  return step;
}

void start_call_watchdog(const CallLimits& limits) {
  g_setup_limit.store(limits.setup, std::memory_order_relaxed);
  g_step_limit.store(limits.step, std::memory_order_relaxed);
  g_record.store(&plugin_call_in_flight(), std::memory_order_relaxed);
  const pid_t self = ::getpid();
  if (g_watched_pid.exchange(self) == self) return;  // this process has its thread
  if (!(limits.setup > 0.0) && !(limits.step > 0.0)) {
    g_watched_pid.store(0);
    return;
  }
  std::thread(watch).detach();
  // Wait until the thread runs its loop. A thread still starting may hold a
  // lock of the C library's or of a sanitizer's runtime; a fork made then
  // (run forks at once) gives a child in which that lock is never released,
  // and the child hangs at its first thread or allocation.
  while (g_running_pid.load(std::memory_order_acquire) != self) std::this_thread::yield();
}

}  // namespace mh::cli
