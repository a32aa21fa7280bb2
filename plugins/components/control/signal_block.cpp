#include "signal_block.hpp"

#include <cmath>

#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/specs.hpp"

namespace ctl {

mh_status add_signal_state(const mh_host* host, const char* name, const char* unit, double initial,
                           double tolerance, int32_t* index, monohydra::TouchedStates& states) {
  const mh_state_spec spec = monohydra::state_spec(name, unit, initial, tolerance);
  if (monohydra::subsystem_setup(host).add_state(host, &spec, index) != MH_OK) return MH_ERROR;
  states.add(*index);
  return MH_OK;
}

mh_status limits_option(const mh_host* host, const char* lower_key, const char* upper_key,
                        double* lower, double* upper) {
  const mh_options_service& options = monohydra::options(host);
  if (options.option_number(host, lower_key, 0, -kInf, lower) != MH_OK ||
      options.option_number(host, upper_key, 0, kInf, upper) != MH_OK)
    return MH_ERROR;
  if (std::isnan(*lower) || *lower == kInf)
    return options.option_error(host, lower_key, "a lower limit below +inf");
  if (std::isnan(*upper) || *upper == -kInf || !(*lower < *upper))
    return options.option_error(host, upper_key, "an upper limit above the lower one");
  return MH_OK;
}

mh_status signal_unit_and_tolerance(const mh_host* host, double default_tolerance,
                                    const char** unit, double* tolerance) {
  if (monohydra::options(host).option_string(host, "unit", 0, "", unit) != MH_OK) return MH_ERROR;
  return positive_option(host, "tolerance", 0, default_tolerance,
                         "a positive Newton tolerance in the signal's unit", tolerance);
}

}  // namespace ctl
