// What every control component shares: its signal input ports (a table, an
// input or a state of the run: option_signal_port), its signal states (the
// output ports other instances connect to by "instance.state"), and options
// checked on reading. A block's output is a state of the run, so a control
// loop's equations join the monolithic Newton with the mechanics and the
// hydraulics, each block giving its analytic derivatives (docs/control.md).
#pragma once

#include <cstdint>
#include <limits>

#include "monohydra/cpp/checked_options.hpp"
#include "monohydra/cpp/signal_port.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/host.h"

namespace ctl {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A signal input port (the SDK's helper): a table, an input or a state.
using SignalInput = monohydra::SignalPort;

// Declares the block's state `name` (the value it gives other blocks) with
// tolerance `tolerance` in the option `unit`'s unit; *index receives it and
// `states` records it.
mh_status add_signal_state(const mh_host* host, const char* name, const char* unit, double initial,
                           double tolerance, int32_t* index, monohydra::TouchedStates& states);

// Option readers that check the value and report `expected` otherwise.
using monohydra::finite_option;
using monohydra::nonnegative_option;
using monohydra::positive_option;

// The output limits `lower_key` <= `upper_key` (missing: unbounded).
mh_status limits_option(const mh_host* host, const char* lower_key, const char* upper_key,
                        double* lower, double* upper);
// The block's `unit` option (a string, "" when absent) and its `tolerance`.
mh_status signal_unit_and_tolerance(const mh_host* host, double default_tolerance,
                                    const char** unit, double* tolerance);

// The value clamped to [lo, hi] and its slope (1 inside, 0 at a limit).
inline double clamp_slope(double v, double lo, double hi, double* slope) {
  if (v <= lo) {
    *slope = 0.0;
    return lo;
  }
  if (v >= hi) {
    *slope = 0.0;
    return hi;
  }
  *slope = 1.0;
  return v;
}

}  // namespace ctl
