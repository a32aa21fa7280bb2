// The plugin call in flight, for a host's crash handler to name: which
// instance (its label: "subsystem 'spring' (spring-damper) of
// monohydra-mechanics.so"), which call ("evaluate"), and the time and step
// being attempted. The engine marks every call into a plugin with a
// PluginCallScope (nested: a subsystem's evaluate inside the formulation's
// residual restores the residual after). The fields are lock-free atomics,
// so a signal handler may read them; the strings live as long as the run.
#pragma once

#include <atomic>

namespace mh {

// One call of one instance: its label and the call's name. Each instance
// holds one per call it can make (built once, at setup), so that marking a
// call is one pointer store.
struct PluginCallSite {
  const char* who = nullptr;
  const char* call = nullptr;
};

struct PluginCallInFlight {
  std::atomic<const PluginCallSite*> site{nullptr};
  std::atomic<double> t{0.0};
  std::atomic<long> step{0};
  // Calls entered so far: a host's watchdog that sees the same call in flight
  // and this count unchanged for a while knows that the call has not returned
  // (a call that makes nested calls keeps counting).
  std::atomic<unsigned long> entered{0};
};

static_assert(std::atomic<const PluginCallSite*>::is_always_lock_free &&
                  std::atomic<double>::is_always_lock_free &&
                  std::atomic<long>::is_always_lock_free &&
                  std::atomic<unsigned long>::is_always_lock_free,
              "a signal handler reads the record: its fields must be lock-free");

// This thread's record: each thread that steps a run marks its own calls (a
// batch steps its runs on several threads; one record written by all of
// them would pass one cache line between the cores at every plugin call and
// name another thread's call). A crash handler runs on the crashing thread
// and reads that thread's; a watchdog thread reads the stepping thread's
// through the address that thread gave it. Constant-initialized, so reading
// it from a signal handler is safe.
inline PluginCallInFlight& plugin_call_in_flight() {
  static thread_local PluginCallInFlight record;
  return record;
}

class PluginCallScope {
 public:
  explicit PluginCallScope(const PluginCallSite& site)
      : record_(plugin_call_in_flight()), previous_(record_.site.load(std::memory_order_relaxed)) {
    record_.site.store(&site, std::memory_order_relaxed);
    // One thread marks its calls: a load and a store, no locked read-modify-write.
    record_.entered.store(record_.entered.load(std::memory_order_relaxed) + 1,
                          std::memory_order_relaxed);
  }
  ~PluginCallScope() { record_.site.store(previous_, std::memory_order_relaxed); }
  PluginCallScope(const PluginCallScope&) = delete;
  PluginCallScope& operator=(const PluginCallScope&) = delete;

 private:
  PluginCallInFlight& record_;
  const PluginCallSite* previous_;
};

}  // namespace mh
