// What every control component shares: its signal input ports (a table, an
// input or a state of the run: option_signal_port), its signal states (the
// output ports other instances connect to by "instance.state"), and options
// checked on reading. A block's output is a state of the run, so a control
// loop's equations join the monolithic Newton with the mechanics and the
// hydraulics, each block giving its analytic derivatives (docs/control.md).
#pragma once

#include <cstdint>
#include <limits>

#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/host.h"

namespace ctl {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A signal input port: its value at each call (written by the host) and the
// state it reads when it is a state of the run (else -1: a table or an input,
// a constant of the unknowns within a call).
class SignalInput {
 public:
  // Reads option `key` (option_signal_port) and records its state, if any, in
  // `states` in the host's order.
  mh_status read(const mh_host* host, const char* key, int required, double fallback,
                 monohydra::TouchedStates& states);
  double value() const { return *value_; }
  // d(row)/d(this input) += slope, when the input is a state.
  void add(monohydra::JacobianBlock& d_dy, int32_t row, double slope) const {
    if (state_ >= 0) d_dy.add(row, state_, slope);
  }

 private:
  const double* value_ = nullptr;
  int32_t state_ = -1;
};

// Declares the block's state `name` (the value it gives other blocks) with
// tolerance `tolerance` in the option `unit`'s unit; *index receives it and
// `states` records it.
mh_status add_signal_state(const mh_host* host, const char* name, const char* unit, double initial,
                           double tolerance, int32_t* index, monohydra::TouchedStates& states);

// Option readers that check the value and report `expected` otherwise.
mh_status finite_option(const mh_host* host, const char* key, int required, double fallback,
                        const char* expected, double* out);
mh_status positive_option(const mh_host* host, const char* key, int required, double fallback,
                          const char* expected, double* out);
mh_status nonnegative_option(const mh_host* host, const char* key, int required, double fallback,
                             const char* expected, double* out);
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
