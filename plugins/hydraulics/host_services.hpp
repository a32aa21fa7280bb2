// The host calls every hydraulic component makes: options checked on reading,
// ports on hydraulic nodes, the ABI 1.1 check, and log lines.
#pragma once

#include <cstdint>
#include <string>

#include "monohydra/host.h"

namespace hyd {

// Reads option `key` into *out and checks it is finite and > 0, else reports
// `expected` through option_error. A missing optional key yields `fallback`.
mh_status positive_option(const mh_host* host, const char* key, int required, double fallback,
                          const char* expected, double* out);

// True when the host has the ABI 1.1 services the hydraulic components need
// (add_port, point_position); otherwise logs why `component` cannot run.
bool has_ports(const mh_host* host, const char* component);
// True when the host can take time events (add_time_event, ABI 1.1).
bool has_time_events(const mh_host* host);

// Declares a hydraulic port (domain "hydraulic", effort = pressure in Pa):
// *index receives the node's pressure state.
mh_status add_hydraulic_port(const mh_host* host, const char* key, uint32_t role, double initial,
                             double abs_tolerance, int32_t* index);

void log_error(const mh_host* host, const std::string& message);

// A number for messages: 6 significant digits.
std::string fmt(double value);

}  // namespace hyd
