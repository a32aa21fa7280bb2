// What every call of the C API (simulation.h) does around its body: the
// handle of a run, the guard that turns exceptions and the plugins'
// warnings into a status and a message, the refusal, and the start a step
// implies. Shared by the calls on a run (simulation_api.cpp) and on its
// estimator (estimator_api.cpp).
#pragma once

#include <atomic>
#include <exception>
#include <memory>
#include <new>
#include <string>

#include "instance.hpp"
#include "monohydra/simulation.h"

struct mhs_simulation {
  std::unique_ptr<mh::embed::Instance> instance;  // null: the model did not open
  // What the last call that did not return MHS_OK said, kept through the
  // calls that do until the next one that does not, or a restore.
  std::string message;
  bool started = false;
  std::string failure;                 // why the last step failed ("" : it did not)
  std::atomic<bool> in_call{false};    // a thread is in a call on this run
  std::atomic<bool> cancelled{false};  // mhs_cancel: the next look between two steps ends the call
};

namespace mh::embed {

inline constexpr const char* kNullHandle = "the simulation handle is NULL";
inline constexpr const char* kInUse =
    "refused: another thread is in a call on this simulation (a run is used by one thread at a "
    "time; give each thread its own, or a batch: mhs_batch_*)";

// The run this thread was last refused on because another thread was in a
// call on it: its mhs_message is kInUse (the run's own message belongs to
// the other thread's call).
const mhs_simulation*& refused_in_use();

// Marks the run as in a call for as long as it lives; `entered` is false
// when another thread was in one already.
class CallScope {
 public:
  explicit CallScope(mhs_simulation* sim) : sim_(sim) {
    entered_ = !sim->in_call.exchange(true, std::memory_order_acquire);
    if (entered_ && refused_in_use() == sim) refused_in_use() = nullptr;
    if (!entered_) refused_in_use() = sim;
  }
  ~CallScope() {
    if (entered_) sim_->in_call.store(false, std::memory_order_release);
  }
  CallScope(const CallScope&) = delete;
  CallScope& operator=(const CallScope&) = delete;
  bool entered() const { return entered_; }

 private:
  mhs_simulation* sim_;
  bool entered_ = false;
};

// Whether mhs_cancel asked to end the call in flight (taken: the next call
// runs unless asked again).
inline bool cancel_asked(mhs_simulation* sim) {
  return sim->cancelled.exchange(false, std::memory_order_acq_rel);
}

// Runs `body` on an open run: NULL and unopened handles, a second thread's
// call, exceptions and the plugins' warnings become the call's status and
// message.
template <class Body>
mhs_status guarded(mhs_simulation* sim, Body&& body) {
  if (sim == nullptr) return MHS_ERROR;
  const CallScope scope(sim);
  if (!scope.entered()) return MHS_ERROR;
  if (!sim->instance) {
    sim->message = "the model did not open; free this handle (mhs_free)";
    return MHS_FATAL;
  }
  sim->instance->warnings.clear();
  mhs_status status = MHS_OK;
  try {
    status = body(*sim->instance);
  } catch (const std::bad_alloc&) {
    sim->message = "out of memory";
    return MHS_FATAL;
  } catch (const std::exception& err) {
    sim->message = err.what();
    return MHS_ERROR;
  } catch (...) {
    sim->message = "an unknown exception reached the API";
    return MHS_ERROR;
  }
  if (status == MHS_OK && !sim->instance->warnings.empty()) {
    sim->message = sim->instance->warnings;
    return MHS_WARNING;
  }
  return status;
}

inline mhs_status refuse(mhs_simulation* sim, const std::string& why) {
  sim->message = why;
  return MHS_ERROR;
}

// Starts the run when the caller did not.
inline void ensure_started(mhs_simulation* sim, Instance& in) {
  if (sim->started) return;
  in.sim().start();
  sim->started = true;
}

}  // namespace mh::embed
