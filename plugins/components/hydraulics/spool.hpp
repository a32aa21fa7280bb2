// A directional valve's spool U (V) following its reference U_ref(t) with
// first-order dynamics (Eq. 27), the one law of every valve with a spool
// (valve_4_3.cpp, valve_table.cpp):
//   U's row += tau dU/dt - (U_ref(t) - U)
// Options time_constant, reference (a signal port: a time table or one of
// the model's inputs, which the host evaluates and whose jumps are its time
// events, or a state of the run such as a controller's output), initial_spool, tolerance,
// spool_limit; state U (role MH_ROLE_CONTROL_SIGNAL, range [-spool_limit, spool_limit]), output
// U_ref.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/signal_port.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {

class Spool {
 public:
  // Reads the options, declares U and U_ref, adds U to `states`.
  mh_status setup(const mh_host* h, monohydra::TouchedStates& states) {
    double u0 = 0.0, tolerance = 0.0;
    if (positive_option(h, "time_constant", 1, 0.0, "a positive spool time constant tau (s)",
                        &tau_) != MH_OK ||
        reference_.read(h, "reference", 1, 0.0, states) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_spool", 0, 0.0, &u0) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-7, "a positive spool tolerance (V)", &tolerance) !=
            MH_OK ||
        positive_option(h, "spool_limit", 0, 10.0, "a positive spool limit (V)", &limit_) != MH_OK)
      return MH_ERROR;
    if (!std::isfinite(u0))
      return monohydra::options(h).option_error(h, "initial_spool", "a finite spool position (V)");
    mh_state_spec spool = monohydra::state_spec("U", "V", u0, tolerance);
    spool.role = MH_ROLE_CONTROL_SIGNAL;
    spool.range_min = -limit_;
    spool.range_max = limit_;
    if (monohydra::subsystem_setup(h).add_state(h, &spool, &u_) != MH_OK) return MH_ERROR;
    states.add(u_);
    const mh_output_spec u_ref = monohydra::output_spec("U_ref", "V");
    return monohydra::outputs(h).add_output(h, &u_ref, &u_ref_out_);
  }

  int32_t state() const { return u_; }
  double limit() const { return limit_; }

  void evaluate(const mh_subsystem_eval& eval) const {
    const double u_ref = std::clamp(reference_.value(), -limit_, limit_);  // the host's, at eval.t
    eval.residual[u_] += tau_ * eval.ydot[u_] - (u_ref - eval.y[u_]);      // Eq. 27
    eval.outputs[u_ref_out_] = u_ref;
  }
  void jacobian(const monohydra::TouchedStates& states, double* d_dy, double* d_dydot) const {
    monohydra::JacobianBlock(states, d_dy).add(u_, u_, 1.0);
    if (std::abs(reference_.value()) < limit_) {  // a signal port's state: -dU_ref/dstate
      monohydra::JacobianBlock dy(states, d_dy);
      reference_.add(dy, u_, -1.0);
    }
    monohydra::JacobianBlock(states, d_dydot).add(u_, u_, tau_);
  }

  double time_constant() const { return tau_; }
  void set_time_constant(double tau) { tau_ = tau; }

 private:
  double tau_ = 0.0, limit_ = 10.0;
  monohydra::SignalPort reference_;  // a table, an input or a state of the run
  int32_t u_ = -1, u_ref_out_ = -1;
};

}  // namespace hyd
