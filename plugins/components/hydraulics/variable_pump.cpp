// variable-pump: a variable-displacement pump with load-sensing control. Its
// swash plate sets the displacement fraction of D (m^3/rad) at the shaft
// speed w (rad/s). The plate eps (0..1) follows the lower of two
// compensators with a first-order lag tau, and a torque limiter caps the
// displacement it delivers at once (its spool acts on the plate's stroke far
// faster than the compensators settle, so it is taken as instantaneous: the
// shaft's torque never exceeds the limit, by construction):
//   load sensing  e_LS  = (p_LS + dp_m - p_P) / p_b   (holds p_P = p_LS + dp_m,
//                                                      the margin, within eps p_b)
//   cut-off       e_cut = (p_c - p_P) / p_b           (destrokes at p_c)
//   eps_cmd = clamp(smin(e_LS, e_cut), 0, 1)          (dual.hpp's smin, width w_s)
//   eps's row += tau d(eps)/dt + eps - eps_cmd
//   torque limit  e_T = T_max / (D (p_P - p_S))        (T_max, or P_max / w)
//   x = smin(eps, e_T)                                 (the delivered fraction, <= both)
//   Q = x D w - G (p_P - p_S)                          (G: leakage)
//   P's row -= Q,  S's row += Q;  LS takes no flow (a pilot line)
// Outputs: q (m^3/s), x, torque T = x D (p_P - p_S) (N m), shaft power T w (W).
// A proportional compensator (its spool's band p_b, 1e5 Pa by default) as
// the catalogues of load-sensing pumps describe it; sources in
// docs/hydraulics.md.
#include <algorithm>
#include <cmath>
#include <limits>

#include "components.hpp"
#include "dual.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
enum { kP, kS, kLS, kEps, kInputs };
using D = Dual<kInputs>;

// An optional limit: absent, none (infinity); given, finite and > 0.
mh_status limit_option(const mh_host* h, const char* key, const char* expected, double* out) {
  if (monohydra::options(h).option_number(h, key, 0, kInf, out) != MH_OK) return MH_ERROR;
  if (*out == kInf) return MH_OK;
  return *out > 0.0 ? MH_OK : monohydra::options(h).option_error(h, key, expected);
}

class VariablePump {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kVariablePumpExample;

  explicit VariablePump(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double eps0 = 0.0, max_power = kInf;
    if (positive_option(h, "max_displacement", 1, 0.0,
                        "a positive displacement D (m^3/rad: m^3 per revolution / 2 pi)",
                        &d_) != MH_OK ||
        positive_option(h, "speed", 1, 0.0, "a positive shaft speed (rad/s)", &w_) != MH_OK ||
        positive_option(h, "margin", 1, 0.0,
                        "a positive load-sensing margin (Pa): p_P - p_LS the pump holds",
                        &margin_) != MH_OK ||
        positive_option(h, "band", 0, 1e5, "a positive proportional band (Pa) of the compensators",
                        &band_) != MH_OK ||
        positive_option(h, "time_constant", 0, 0.02, "a positive swash-plate time constant (s)",
                        &tau_) != MH_OK ||
        limit_option(h, "cutoff_pressure", "a positive cut-off pressure (Pa)", &cutoff_) != MH_OK ||
        limit_option(h, "max_torque", "a positive torque limit (N m)", &torque_) != MH_OK ||
        limit_option(h, "max_power", "a positive shaft power limit (W)", &max_power) != MH_OK ||
        positive_option(h, "smoothing", 0, 0.01,
                        "a positive smoothing of the limiters (a fraction of full stroke)",
                        &smooth_) != MH_OK)
      return MH_ERROR;
    if (monohydra::options(h).option_number(h, "leakage", 0, 0.0, &leakage_) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_displacement", 0, 0.0, &eps0) != MH_OK)
      return MH_ERROR;
    if (!(leakage_ >= 0.0))
      return monohydra::options(h).option_error(h, "leakage",
                                                "a non-negative leakage (m^3/(s Pa))");
    if (!(eps0 >= 0.0 && eps0 <= 1.0))
      return monohydra::options(h).option_error(h, "initial_displacement",
                                                "a displacement fraction in [0, 1]");
    torque_ = std::min(torque_, max_power / w_);  // the power limit is a torque limit at w
    if (add_hydraulic_port(h, "P", MH_PORT_FLOW, kNaN, kNaN, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    if (add_hydraulic_port(h, "S", MH_PORT_FLOW, kNaN, kNaN, &s_) != MH_OK) return MH_ERROR;
    states_.add(s_);
    if (add_hydraulic_port(h, "LS", MH_PORT_FLOW, kNaN, kNaN, &ls_) != MH_OK) return MH_ERROR;
    states_.add(ls_);
    const mh_state_spec eps = monohydra::state_spec("eps", "", eps0, 1e-8);
    if (monohydra::subsystem_setup(h).add_state(h, &eps, &eps_) != MH_OK) return MH_ERROR;
    states_.add(eps_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    const mh_output_spec delivered = monohydra::output_spec("x", "");
    const mh_output_spec torque = monohydra::output_spec("T", "N m");
    const mh_output_spec power = monohydra::output_spec("P", "W");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &delivered, &x_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &torque, &torque_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &power, &power_out_) != MH_OK)
      return MH_ERROR;
    return MH_OK;
  }

  // The plate's command, the delivered fraction and the flow, with their
  // derivatives in p_P, p_S, p_LS and eps.
  struct Law {
    D command, delivered, flow, torque;
  };
  Law law(const mh_subsystem_eval& eval) const {
    const D p = D::input(eval.y[p_], kP), s = D::input(eval.y[s_], kS);
    const D ls = D::input(eval.y[ls_], kLS), eps = D::input(eval.y[eps_], kEps);
    D e = (1.0 / band_) * (ls + margin_ - p);  // load sensing
    if (std::isfinite(cutoff_))
      e = smooth_min(e, (1.0 / band_) * (D::constant(cutoff_) - p), smooth_);
    Law l;
    l.command = smooth_max(smooth_min(e, D::constant(1.0), smooth_), D::constant(0.0), smooth_);
    l.delivered = eps;
    if (std::isfinite(torque_)) {
      // below 1 bar of pressure rise the torque limit is out of reach
      const D rise = smooth_max(p - s, D::constant(1e5), 1e4);
      l.delivered = smooth_min(eps, divide(D::constant(torque_ / d_), rise), smooth_);
    }
    l.flow = (d_ * w_) * l.delivered - leakage_ * (p - s);
    l.torque = d_ * (l.delivered * (p - s));
    return l;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const Law l = law(eval);
    eval.residual[eps_] += tau_ * eval.ydot[eps_] + eval.y[eps_] - l.command.v;
    eval.residual[p_] -= l.flow.v;
    eval.residual[s_] += l.flow.v;
    eval.outputs[q_out_] = l.flow.v;
    eval.outputs[x_out_] = l.delivered.v;
    eval.outputs[torque_out_] = l.torque.v;
    eval.outputs[power_out_] = l.torque.v * w_;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    const Law l = law(eval);
    const int32_t of[kInputs] = {p_, s_, ls_, eps_};
    monohydra::JacobianBlock dy(states_, d_dy);
    for (int k = 0; k < kInputs; ++k) {
      dy.add(eps_, of[k], (k == kEps ? 1.0 : 0.0) - l.command.d[static_cast<size_t>(k)]);
      dy.add(p_, of[k], -l.flow.d[static_cast<size_t>(k)]);
      dy.add(s_, of[k], l.flow.d[static_cast<size_t>(k)]);
    }
    monohydra::JacobianBlock(states_, d_dydot).add(eps_, eps_, tau_);
    return MH_OK;
  }

  // The shaft's power goes into the fluid (Q (p_P - p_S)) but for the
  // leakage's throttling: nothing stored; the leakage dissipates.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const double rise = eval.y[p_] - eval.y[s_];
    stored = 0.0;
    dissipation = leakage_ * rise * rise;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double d_ = 0.0, w_ = 0.0, margin_ = 0.0, band_ = 1e5, tau_ = 0.02;
  double cutoff_ = kInf, torque_ = kInf, smooth_ = 0.01, leakage_ = 0.0;
  int32_t p_ = -1, s_ = -1, ls_ = -1, eps_ = -1;
  int32_t q_out_ = -1, x_out_ = -1, torque_out_ = -1, power_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor VariablePump::kDescriptor{
    sizeof(mh_component_descriptor),
    "variable-pump",
    "Variable-displacement pump with load sensing",
    "monohydra",
    "1.0.0",
    "Delivers x max_displacement speed from S to P; its swash plate (eps in [0, 1], lag "
    "time_constant, default 0.02 s) follows the lower of a load-sensing compensator (p_P = p_LS "
    "+ margin within eps band, band default 1e5 Pa) and a pressure cut-off (cutoff_pressure); "
    "a torque limiter (max_torque, or max_power at speed) caps the delivered x at once. Options "
    "also: leakage (m^3/(s Pa)), initial_displacement, smoothing (default 0.01). State eps; "
    "outputs q (m^3/s), x, T (N m), P (W)."};

}  // namespace

const monohydra::SubsystemComponent kVariablePump = monohydra::subsystem_component<VariablePump>();

}  // namespace hyd
