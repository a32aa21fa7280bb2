// The host calls every hydraulic component makes: options checked on reading,
// ports on hydraulic nodes, and log lines.
#pragma once

#include <cstdint>
#include <string>

#include "monohydra/cpp/number_text.hpp"
#include "monohydra/host.h"

namespace hyd {

// Reads option `key` into *out and checks it is finite and > 0, else reports
// `expected` through option_error. A missing optional key yields `fallback`.
mh_status positive_option(const mh_host* host, const char* key, int required, double fallback,
                          const char* expected, double* out);

// Declares a hydraulic port (domain "hydraulic", effort = pressure in Pa):
// *index receives the node's pressure state.
mh_status add_hydraulic_port(const mh_host* host, const char* key, uint32_t role, double initial,
                             double abs_tolerance, int32_t* index);

void log_error(const mh_host* host, const std::string& message);

// A number for messages: 6 significant digits.
using monohydra::short_number;

}  // namespace hyd
