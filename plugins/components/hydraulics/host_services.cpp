#include "host_services.hpp"

#include <cmath>
#include <cstdio>

#include "monohydra/cpp/services.hpp"
#include "monohydra/host.h"

namespace hyd {

mh_status add_hydraulic_port(const mh_host* host, const char* key, uint32_t role, double initial,
                             double abs_tolerance, int32_t* index) {
  mh_port_spec spec{};
  spec.struct_size = sizeof(mh_port_spec);
  spec.key = key;
  spec.domain = "hydraulic";
  spec.unit = "Pa";
  spec.role = role;
  spec.initial = initial;
  spec.abs_tolerance = abs_tolerance;
  return monohydra::subsystem_setup(host).add_port(host, &spec, index);
}

void log_error(const mh_host* host, const std::string& message) {
  host->log(host, MH_LOG_ERROR, message.c_str());
}

}  // namespace hyd
