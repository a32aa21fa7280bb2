// Thin wrappers over the host services the double-step plugin uses.
#pragma once

#include <cstdio>
#include <string>

#include "monohydra/cpp/number_text.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/monohydra.h"

namespace mh::double_step {

// evaluate_mechanics at (t, z, zd) with the MH_EVAL_* flags; `out` receives the
// host's buffers, valid until the next call.
inline mh_status evaluate(const mh_host* host, const mh_mechanism_service& mech, uint32_t flags,
                          double t, const double* z, const double* zd, mh_mech_result& out) {
  const mh_mech_request request{sizeof(mh_mech_request), flags, t, z, zd};
  out = mh_mech_result{};
  out.struct_size = sizeof(mh_mech_result);
  return mech.evaluate_mechanics(host, &request, &out);
}

inline void log(const mh_host* host, mh_log_level level, const std::string& message) {
  host->log(host, level, message.c_str());
}

// A number for a log line: 6 significant digits, as the host writes them.
using monohydra::short_number;

}  // namespace mh::double_step
