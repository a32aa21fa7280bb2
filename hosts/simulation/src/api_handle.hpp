// What every call of the C API (simulation.h) does around its body: the
// handle of a run, the guard that turns exceptions and the plugins'
// warnings into a status and a message, the refusal, and the start a step
// implies. Shared by the calls on a run (simulation_api.cpp) and on its
// estimator (estimator_api.cpp).
#pragma once

#include <exception>
#include <memory>
#include <new>
#include <string>

#include "instance.hpp"
#include "monohydra/simulation.h"

struct mhs_simulation {
  std::unique_ptr<mh::embed::Instance> instance;  // null: the model did not open
  std::string message;
  bool started = false;
  std::string failure;  // why the last step failed ("" : it did not)
};

namespace mh::embed {

inline constexpr const char* kNullHandle = "the simulation handle is NULL";

// Runs `body` on an open run: NULL and unopened handles, exceptions and the
// plugins' warnings become the call's status and message.
template <class Body>
mhs_status guarded(mhs_simulation* sim, Body&& body) {
  if (sim == nullptr) return MHS_ERROR;
  sim->message.clear();
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
