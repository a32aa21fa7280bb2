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
#include <utility>

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

// The handle of each kind (a run, a batch) this thread was last refused on
// because another thread was in a call on it: its message is the refusal
// (the handle's own message belongs to the other thread's call).
template <class Handle>
const Handle*& refused_in_use() {
  thread_local const Handle* handle = nullptr;
  return handle;
}

// Marks a handle (its `in_call`) as in a call for as long as it lives;
// `entered` is false when another thread was in one already.
template <class Handle>
class CallScope {
 public:
  explicit CallScope(Handle* h) : h_(h) {
    entered_ = !h->in_call.exchange(true, std::memory_order_acquire);
    if (entered_ && refused_in_use<Handle>() == h) refused_in_use<Handle>() = nullptr;
    if (!entered_) refused_in_use<Handle>() = h;
  }
  ~CallScope() {
    if (entered_) h_->in_call.store(false, std::memory_order_release);
  }
  CallScope(const CallScope&) = delete;
  CallScope& operator=(const CallScope&) = delete;
  bool entered() const { return entered_; }

 private:
  Handle* h_;
  bool entered_ = false;
};

// Runs `body` on what the handle opened (`opened(*h)`, null when the model
// did not open): NULL and unopened handles, a second thread's call,
// exceptions and the plugins' warnings (`take_warnings`: what they said
// since it was last called) become the call's status and the handle's
// `message`. `free_call` names the call that frees an unopened handle.
template <class Handle, class Opened, class TakeWarnings, class Body>
mhs_status guarded_call(Handle* h, Opened&& opened, TakeWarnings&& take_warnings,
                        const char* free_call, Body&& body) {
  if (h == nullptr) return MHS_ERROR;
  const CallScope<Handle> scope(h);
  if (!scope.entered()) return MHS_ERROR;
  auto* object = opened(*h);
  if (object == nullptr) {
    h->message = std::string("the model did not open; free this handle (") + free_call + ")";
    return MHS_FATAL;
  }
  take_warnings(*object);  // an earlier call's, left by its exception
  mhs_status status = MHS_OK;
  try {
    status = body(*object);
  } catch (const std::bad_alloc&) {
    h->message = "out of memory";
    return MHS_FATAL;
  } catch (const std::exception& err) {
    h->message = err.what();
    return MHS_ERROR;
  } catch (...) {
    h->message = "an unknown exception reached the API";
    return MHS_ERROR;
  }
  const std::string warnings = take_warnings(*object);
  if (status == MHS_OK && !warnings.empty()) {
    h->message = warnings;
    return MHS_WARNING;
  }
  return status;
}

// Whether mhs_cancel asked to end the call in flight (taken: the next call
// runs unless asked again).
inline bool cancel_asked(mhs_simulation* sim) {
  return sim->cancelled.exchange(false, std::memory_order_acq_rel);
}

// Runs `body` on an open run (guarded_call).
template <class Body>
mhs_status guarded(mhs_simulation* sim, Body&& body) {
  return guarded_call(
      sim, [](mhs_simulation& s) { return s.instance.get(); },
      [](Instance& in) {
        std::string said = std::move(in.warnings);
        in.warnings.clear();
        return said;
      },
      "mhs_free", std::forward<Body>(body));
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
