// monohydra SDK, optional C++17 helper (header-only): the C boundary's guard.
// No exception may cross into the host: every operation a C++ plugin exports
// runs inside `guarded`, which logs an escaping exception through the host as
// "<op>: <what>" and returns MH_ERROR instead.
#pragma once

#include <exception>
#include <string>
#include <utility>

#include "monohydra/host.h"

namespace monohydra {

namespace detail {

// Logs "<what>: <reason>" without throwing (a failed allocation logs `what` alone).
inline void log_failure(const mh_host* host, const char* what, const char* reason) noexcept {
  if (host == nullptr || host->log == nullptr) return;
  try {
    host->log(host, MH_LOG_ERROR, (std::string(what) + ": " + reason).c_str());
  } catch (...) {
    host->log(host, MH_LOG_ERROR, what);
  }
}

}  // namespace detail

// Runs `op` (returning mh_status); an exception escaping it is logged through
// `host` as "<what>: <exception text>" and turns into MH_ERROR.
template <class Op>
mh_status guarded(const mh_host* host, const char* what, Op&& op) noexcept {
  try {
    return std::forward<Op>(op)();
  } catch (const std::exception& e) {
    detail::log_failure(host, what, e.what());
  } catch (...) {
    detail::log_failure(host, what, "unknown C++ exception");
  }
  return MH_ERROR;
}

}  // namespace monohydra
