// monohydra SDK, optional C++17 helper (header-only): a component's signal
// input port (host.h, option_signal_port). It reads the option (a number, a
// table, an input or a state of the run), keeps the value the host writes
// before each call and, when the port reads a state, that state: recorded in
// the instance's TouchedStates in the host's order, so the jacobian can add
// the derivative of a row in it.
//
//   monohydra::SignalPort reference;
//   if (reference.read(host, "reference", 1, 0.0, states_) != MH_OK) return MH_ERROR;
//   ... eval.residual[u_] += tau * eval.ydot[u_] - (reference.value() - eval.y[u_]);
//   ... reference.add(d_dy, u_, -1.0);   // in jacobian
#pragma once

#include <cstdint>

#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/host.h"

namespace monohydra {

class SignalPort {
 public:
  mh_status read(const mh_host* host, const char* key, int required, double fallback,
                 TouchedStates& states) {
    mh_signal signal{};
    signal.struct_size = sizeof signal;
    if (signal_port(host, key, required, fallback, &signal) != MH_OK) return MH_ERROR;
    if (signal.value == nullptr) {  // a host that broke its contract
      if (host != nullptr && host->log != nullptr)
        host->log(host, MH_LOG_ERROR, "the host gave a signal port no value");
      return MH_ERROR;
    }
    value_ = signal.value;
    state_ = signal.state;
    if (state_ >= 0) states.add(state_);  // the host touched it at this call
    return MH_OK;
  }
  // The value at the current call (the host's, written before it).
  double value() const { return *value_; }
  // The state it reads, or -1 (a number, a table, an input).
  int32_t state() const { return state_; }
  // d(row)/d(this port) += slope, when it reads a state.
  void add(JacobianBlock& d_dy, int32_t row, double slope) const {
    if (state_ >= 0) d_dy.add(row, state_, slope);
  }

 private:
  static constexpr double kUnread = 0.0;  // the value before read()
  const double* value_ = &kUnread;
  int32_t state_ = -1;
};

}  // namespace monohydra
