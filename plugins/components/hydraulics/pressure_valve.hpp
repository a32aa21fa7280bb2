// A pressure-opened poppet valve between an inlet and an outlet node: the
// relief valve (relief_valve.cpp) and the check valve (check_valve.cpp) are
// both a spring-loaded poppet that the pressure difference dp = p_in - p_out
// lifts off its seat at the cracking pressure p_cr and opens fully over the
// override p_ov (the catalogue's pressure-flow gradient). The two differ only
// in their ports' names and descriptors (the Traits).
//
//   u = (dp - p_cr) / p_ov                      opening coordinate
//   x(u) = r(u) - r(u - 1)                      opening in [0, 1]
//   r(u) = 0 (u <= 0), u^2 / (2 d) (0 < u < d), u - d / 2 (u >= d)
//   Q = C x(u) g(dp),  g(dp) = dp / (dp^2 + p_tr^2)^(1/4)
//   C = Q_nom / (x(u_nom) g(p_nom))             the catalogue point (p_nom, Q_nom)
//   in's row += Q,  out's row -= Q
//
// r is the ramp with its corner rounded over d (`smoothing`): x and Q are
// continuously differentiable everywhere (Newton's tangent exists) and Q is
// exactly zero for dp <= p_cr (no leakage when closed, no backflow). g is the
// orifice law sqrt(dp) made smooth and linear near dp = 0 (it differs from
// sqrt(dp) by less than 1 % above 5 p_tr).
#pragma once

#include <cmath>
#include <limits>
#include <string>

#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/subsystem_component.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {

class PoppetLaw {
 public:
  PoppetLaw() = default;
  PoppetLaw(double cracking, double override_pressure, double smoothing, double transition)
      : p_cr_(cracking), p_ov_(override_pressure), d_(smoothing), p_tr2_(transition * transition) {}

  // Sets C so that the open valve passes q_nom at the pressure drop p_nom.
  void calibrate(double p_nom, double q_nom) {
    c_ = q_nom / (opening((p_nom - p_cr_) / p_ov_) * orifice(p_nom));
  }

  // Q (m^3/s) at dp (Pa) and dQ/d(dp).
  double flow(double dp) const { return c_ * opening(u(dp)) * orifice(dp); }
  double slope(double dp) const {
    const double x = opening(u(dp));
    if (x == 0.0) return 0.0;
    return c_ * (opening_slope(u(dp)) / p_ov_ * orifice(dp) + x * orifice_slope(dp));
  }
  double opening_at(double dp) const { return opening(u(dp)); }

  // The pieces, public for the tests and the docs' formulas.
  double opening(double u) const { return ramp(u) - ramp(u - 1.0); }
  double opening_slope(double u) const { return ramp_slope(u) - ramp_slope(u - 1.0); }
  double orifice(double dp) const { return dp / std::pow(dp * dp + p_tr2_, 0.25); }
  double orifice_slope(double dp) const {
    const double s = dp * dp + p_tr2_;
    return (0.5 * dp * dp + p_tr2_) / std::pow(s, 1.25);
  }
  double coefficient() const { return c_; }

 private:
  double u(double dp) const { return (dp - p_cr_) / p_ov_; }
  double ramp(double u) const {
    if (u <= 0.0) return 0.0;
    if (u < d_) return 0.5 * u * u / d_;
    return u - 0.5 * d_;
  }
  double ramp_slope(double u) const {
    if (u <= 0.0) return 0.0;
    if (u < d_) return u / d_;
    return 1.0;
  }

  double p_cr_ = 0.0, p_ov_ = 1.0, d_ = 0.1, p_tr2_ = 4e10;
  double c_ = 0.0;  // m^3/(s sqrt(Pa))
};

// The shape options of every poppet valve (PoppetLaw's d and p_tr), read and
// checked in one place: `smoothing` in (0, 1] (a fraction of the override,
// default 0.1) and `transition_pressure` (Pa, default 2e5).
inline mh_status read_poppet_shape(const mh_host* h, double* smoothing, double* transition) {
  if (positive_option(h, "smoothing", 0, 0.1,
                      "a positive smoothing in (0, 1] (a fraction of the override)",
                      smoothing) != MH_OK ||
      positive_option(h, "transition_pressure", 0, 2e5,
                      "a positive laminar-turbulent transition pressure (Pa)", transition) != MH_OK)
    return MH_ERROR;
  if (*smoothing > 1.0)
    return monohydra::options(h).option_error(h, "smoothing",
                                              "a smoothing in (0, 1] (a fraction of the override)");
  return MH_OK;
}

// The component: Traits gives kInlet, kOutlet (port keys), kMinCracking (the
// smallest cracking pressure accepted) and the descriptor.
template <class Traits>
class PressureValve {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = Traits::kExampleModel;

  explicit PressureValve(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double cracking = 0.0, override_pressure = 0.0, q_nom = 0.0, smoothing = 0.0, p_tr = 0.0;
    if (monohydra::options(h).option_number(h, "cracking_pressure", 1, 0.0, &cracking) != MH_OK)
      return MH_ERROR;
    if (!(cracking >= Traits::kMinCracking))
      return monohydra::options(h).option_error(h, "cracking_pressure", Traits::kCrackingExpected);
    if (positive_option(h, "override_pressure", 1, 0.0,
                        "a positive override (Pa): the pressure rise from cracking to fully open",
                        &override_pressure) != MH_OK ||
        positive_option(h, "nominal_flow", 1, 0.0, "a positive nominal flow (m^3/s)", &q_nom) !=
            MH_OK ||
        read_poppet_shape(h, &smoothing, &p_tr) != MH_OK)
      return MH_ERROR;
    const double full = cracking + override_pressure;
    double p_nom = full;
    if (monohydra::options(h).option_number(h, "nominal_pressure", 0, full, &p_nom) != MH_OK)
      return MH_ERROR;
    if (!(p_nom >= full))
      return monohydra::options(h).option_error(
          h, "nominal_pressure",
          ("a pressure drop at or above cracking_pressure + override_pressure = " +
           short_number(full) + " Pa (where the valve is open and passes nominal_flow)")
              .c_str());
    law_ = PoppetLaw(cracking, override_pressure, smoothing, p_tr);
    law_.calibrate(p_nom, q_nom);
    if (add_hydraulic_port(h, Traits::kInlet, MH_PORT_FLOW, kNaN, kNaN, &in_) != MH_OK)
      return MH_ERROR;
    states_.add(in_);
    if (add_hydraulic_port(h, Traits::kOutlet, MH_PORT_FLOW, kNaN, kNaN, &out_) != MH_OK)
      return MH_ERROR;
    states_.add(out_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    return monohydra::outputs(h).add_output(h, &q, &q_out_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double q = law_.flow(eval.y[in_] - eval.y[out_]);
    eval.residual[in_] += q;
    eval.residual[out_] -= q;
    eval.outputs[q_out_] = q;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double*) const {
    const double dq = law_.slope(eval.y[in_] - eval.y[out_]);  // dQ/dp_in = -dQ/dp_out
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(in_, in_, dq);
    dy.add(in_, out_, -dq);
    dy.add(out_, in_, -dq);
    dy.add(out_, out_, dq);
    return MH_OK;
  }

  // Nothing stored; the throttling dissipates Q dp >= 0 (Q > 0 only for dp > p_cr >= 0).
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const double dp = eval.y[in_] - eval.y[out_];
    stored = 0.0;
    dissipation = law_.flow(dp) * dp;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  PoppetLaw law_;
  int32_t in_ = -1, out_ = -1, q_out_ = -1;
  monohydra::TouchedStates states_;
};

}  // namespace hyd
