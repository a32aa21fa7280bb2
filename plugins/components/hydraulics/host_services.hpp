// The host calls every hydraulic component makes: options checked on reading,
// ports on hydraulic nodes, and log lines.
#pragma once

#include <cstdint>
#include <string>

#include "monohydra/cpp/checked_options.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/host.h"

namespace hyd {

// Option `key`, finite and > 0, else reported with `expected` (SDK helper).
using monohydra::positive_option;

// Declares a hydraulic port (domain "hydraulic", effort = pressure in Pa):
// *index receives the node's pressure state.
mh_status add_hydraulic_port(const mh_host* host, const char* key, uint32_t role, double initial,
                             double abs_tolerance, int32_t* index);

void log_error(const mh_host* host, const std::string& message);

// A number for messages: 6 significant digits.
using monohydra::short_number;

}  // namespace hyd
