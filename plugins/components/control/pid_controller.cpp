// pi-controller and pid-controller: a PI(D) on the error e = setpoint -
// measurement, its output saturated, its integrator kept from winding up by
// back-calculation (Astrom and Hagglund, Advanced PID Control, 2006, Sect.
// 3.5):
//   v = kp e + i + kd (e - w) / Tf           (the unsaturated command)
//   u = min(max(v, output_min), output_max)   (state u: algebraic)
//   di/dt = ki e + (u - v) / Tt               (state i: the integral term)
//   Tf dw/dt = e - w                          (state w, PID only: the filtered
//                                              error, so D = kd s / (1 + Tf s))
// Every row's derivatives are analytic, in the states the ports read too.
#include <cmath>

#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

template <bool kDerivative>
class PidController {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit PidController(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    const char* unit = "";
    double tolerance = 0.0, i0 = 0.0;
    if (setpoint_.read(h, "setpoint", 1, 0.0, states_) != MH_OK ||
        measurement_.read(h, "measurement", 1, 0.0, states_) != MH_OK ||
        nonnegative_option(h, "kp", 1, 0.0, "a proportional gain kp >= 0", &kp_) != MH_OK ||
        nonnegative_option(h, "ki", 1, 0.0, "an integral gain ki >= 0 (1/s)", &ki_) != MH_OK ||
        limits_option(h, "output_min", "output_max", &lo_, &hi_) != MH_OK ||
        finite_option(h, "initial_integral", 0, 0.0, "a finite initial integral term", &i0) !=
            MH_OK ||
        signal_unit_and_tolerance(h, 1e-9, &unit, &tolerance) != MH_OK)
      return MH_ERROR;
    if (kDerivative &&
        (nonnegative_option(h, "kd", 1, 0.0, "a derivative gain kd >= 0 (s)", &kd_) != MH_OK ||
         positive_option(h, "filter_time_constant", 0, 0.01,
                         "a positive derivative filter time constant Tf (s)", &tf_) != MH_OK))
      return MH_ERROR;
    // Tt = sqrt(Ti Td) for a PID, Ti for a PI (Ti = kp / ki, Td = kd / kp).
    const double ti = kp_ > 0.0 && ki_ > 0.0 ? kp_ / ki_ : 1.0;
    const double fallback_tt =
        kDerivative && kd_ > 0.0 && kp_ > 0.0 ? std::sqrt(ti * kd_ / kp_) : ti;
    if (positive_option(h, "tracking_time", 0, fallback_tt,
                        "a positive anti-windup tracking time Tt (s)", &tt_) != MH_OK)
      return MH_ERROR;
    if (add_signal_state(h, "i", unit, i0, tolerance, &i_, states_) != MH_OK) return MH_ERROR;
    if (kDerivative && add_signal_state(h, "w", unit, 0.0, tolerance, &w_, states_) != MH_OK)
      return MH_ERROR;
    return add_signal_state(h, "u", unit, 0.0, tolerance, &u_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double e = setpoint_.value() - measurement_.value();
    const double w = kDerivative ? eval.y[w_] : 0.0;
    const double v = kp_ * e + eval.y[i_] + (kDerivative ? kd_ * (e - w) / tf_ : 0.0);
    double slope = 0.0;
    const double u = clamp_slope(v, lo_, hi_, &slope);
    eval.residual[u_] += eval.y[u_] - u;
    eval.residual[i_] += eval.ydot[i_] - ki_ * e - (u - v) / tt_;
    if (kDerivative) eval.residual[w_] += tf_ * eval.ydot[w_] - (e - w);
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    const double e = setpoint_.value() - measurement_.value();
    const double w = kDerivative ? eval.y[w_] : 0.0;
    const double v = kp_ * e + eval.y[i_] + (kDerivative ? kd_ * (e - w) / tf_ : 0.0);
    double slope = 0.0;
    clamp_slope(v, lo_, hi_, &slope);
    const double dv_de = kp_ + (kDerivative ? kd_ / tf_ : 0.0);
    monohydra::JacobianBlock dy(states_, d_dy), dydot(states_, d_dydot);
    // u - sat(v): d/dx = -slope dv/dx.
    dy.add(u_, u_, 1.0);
    dy.add(u_, i_, -slope);
    setpoint_.add(dy, u_, -slope * dv_de);
    measurement_.add(dy, u_, slope * dv_de);
    // di/dt - ki e - (sat(v) - v) / Tt: d/dx = -ki de/dx - (slope - 1) dv/dx / Tt.
    const double back = (slope - 1.0) / tt_;
    dydot.add(i_, i_, 1.0);
    dy.add(i_, i_, -back);
    setpoint_.add(dy, i_, -ki_ - back * dv_de);
    measurement_.add(dy, i_, ki_ + back * dv_de);
    if (kDerivative) {
      const double dv_dw = -kd_ / tf_;
      dy.add(u_, w_, -slope * dv_dw);
      dy.add(i_, w_, -back * dv_dw);
      // Tf dw/dt - (e - w).
      dydot.add(w_, w_, tf_);
      dy.add(w_, w_, 1.0);
      setpoint_.add(dy, w_, -1.0);
      measurement_.add(dy, w_, 1.0);
    }
    return MH_OK;
  }

 private:
  const mh_host* host_;
  SignalInput setpoint_, measurement_;
  double kp_ = 0.0, ki_ = 0.0, kd_ = 0.0, tf_ = 0.01, tt_ = 1.0;
  double lo_ = -kInf, hi_ = kInf;
  int32_t i_ = -1, w_ = -1, u_ = -1;
  monohydra::TouchedStates states_;
};

template <>
const mh_component_descriptor PidController<false>::kDescriptor{
    sizeof(mh_component_descriptor),
    "pi-controller",
    "PI controller with anti-windup",
    "monohydra",
    "1.0.0",
    "u = sat(kp e + i), e = setpoint - measurement, di/dt = ki e + (u - v)/Tt (back-calculation "
    "anti-windup). Options: setpoint, measurement (signal ports), kp, ki (1/s), output_min, "
    "output_max (default unbounded), tracking_time Tt (s, default kp/ki), initial_integral "
    "(default 0), unit (of u), tolerance (default 1e-9). States i, u (algebraic)."};

template <>
const mh_component_descriptor PidController<true>::kDescriptor{
    sizeof(mh_component_descriptor),
    "pid-controller",
    "PID controller with anti-windup",
    "monohydra",
    "1.0.0",
    "u = sat(kp e + i + kd (e - w)/Tf), e = setpoint - measurement, di/dt = ki e + (u - v)/Tt, "
    "Tf dw/dt = e - w. Options: as pi-controller, and kd (s), filter_time_constant Tf (s, "
    "default 0.01); tracking_time defaults to sqrt(Ti Td). States i, w, u (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kPiController =
    monohydra::subsystem_component<PidController<false>>();
const monohydra::SubsystemComponent kPidController =
    monohydra::subsystem_component<PidController<true>>();

}  // namespace ctl
