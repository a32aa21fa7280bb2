// counterbalance-valve: the over-centre valve on a load-holding cylinder
// chamber (port L), between it and the line to the directional valve (port
// V), piloted from the opposite line (port X). Two paths in one body:
//  - a relief poppet L -> V that the load pressure and the pilot open
//    together, p_L + R p_X >= p_set (R the pilot ratio, p_set the setting;
//    the spring chamber vented, so p_V does not act): the load is held until
//    the operator pressurizes the opposite side, and a load that runs ahead
//    drops the pilot pressure and closes the valve again (the lowering is
//    metered by the inflow to the other side, it cannot run away);
//  - a check V -> L for free flow when lifting.
//   u = (p_L - p_ref + R (p_X - p_ref) - p_set) / p_ov,  x = r(u) - r(u - 1)
//   (pressure_valve.hpp; p_ref the drain's pressure, 1e5 Pa by default)
//   Q_main = C x g(p_L - p_V),  C = Q_nom / g(p_nom)  (fully open: Q_nom at p_nom)
//   Q_check = the check law on p_V - p_L (cracking p_c, override p_co), passing
//             Q_nom at p_c + p_co + p_nom
//   Q_leak = G (p_L - p_V)  (G = leakage, 0 by default: a seated poppet seals)
//   L's row += Q_main + Q_leak - Q_check,  V's row -= the same; X takes no flow.
// Sources: docs/hydraulics.md (the over-centre valve's force balance as in
// Hopsan's and Simscape Fluids' counterbalance valves).
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "pressure_valve.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class CounterbalanceValve {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kCounterbalanceValveExample;

  explicit CounterbalanceValve(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double smoothing = 0.0, p_tr = 0.0, check_cracking = 0.0, check_override = 0.0;
    if (positive_option(h, "setting_pressure", 1, 0.0,
                        "a positive setting (Pa): the load pressure that opens the valve without "
                        "pilot",
                        &p_set_) != MH_OK ||
        positive_option(h, "pilot_ratio", 1, 0.0, "a positive pilot ratio (e.g. 3 to 10)",
                        &ratio_) != MH_OK ||
        positive_option(h, "override_pressure", 1, 0.0,
                        "a positive override (Pa): the rise of p_L + R p_X from cracking to "
                        "fully open",
                        &p_ov_) != MH_OK ||
        positive_option(h, "nominal_flow", 1, 0.0, "a positive nominal flow (m^3/s)", &q_nom_) !=
            MH_OK ||
        positive_option(h, "nominal_pressure", 0, 1e6,
                        "a positive pressure drop (Pa) at which the open valve passes nominal_flow",
                        &p_nom_) != MH_OK ||
        read_poppet_shape(h, &smoothing, &p_tr) != MH_OK ||
        positive_option(h, "check_override_pressure", 0, 2e5,
                        "a positive override of the check (Pa)", &check_override) != MH_OK)
      return MH_ERROR;
    if (monohydra::options(h).option_number(h, "check_cracking_pressure", 0, 3e4,
                                            &check_cracking) != MH_OK ||
        monohydra::options(h).option_number(h, "leakage", 0, 0.0, &leakage_) != MH_OK ||
        monohydra::options(h).option_number(h, "reference_pressure", 0, 1e5, &p_ref_) != MH_OK)
      return MH_ERROR;
    if (!(check_cracking >= 0.0))
      return monohydra::options(h).option_error(h, "check_cracking_pressure",
                                                "a non-negative cracking pressure (Pa)");
    if (!(leakage_ >= 0.0))
      return monohydra::options(h).option_error(h, "leakage",
                                                "a non-negative leakage conductance (m^3/(s Pa))");
    shape_ = PoppetLaw(0.0, 1.0, smoothing, p_tr);
    c_ = q_nom_ / shape_.orifice(p_nom_);
    check_ = PoppetLaw(check_cracking, check_override, smoothing, p_tr);
    check_.calibrate(check_cracking + check_override + p_nom_, q_nom_);

    if (add_hydraulic_port(h, "L", MH_PORT_FLOW, kNaN, kNaN, &l_) != MH_OK) return MH_ERROR;
    states_.add(l_);
    if (add_hydraulic_port(h, "V", MH_PORT_FLOW, kNaN, kNaN, &v_) != MH_OK) return MH_ERROR;
    states_.add(v_);
    if (add_hydraulic_port(h, "X", MH_PORT_FLOW, kNaN, kNaN, &x_) != MH_OK) return MH_ERROR;
    states_.add(x_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    const mh_output_spec opening = monohydra::output_spec("x", "");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &opening, &x_out_) != MH_OK)
      return MH_ERROR;
    return MH_OK;
  }

  // The flows at the pressures of `eval`, and their derivatives.
  struct Flows {
    double opening = 0.0, main = 0.0, check = 0.0, leak = 0.0;
    double dmain_dl = 0.0, dmain_dv = 0.0, dmain_dx = 0.0, dcheck = 0.0;
    double net() const { return main + leak - check; }  // L -> V
  };
  Flows flows(const mh_subsystem_eval& eval) const {
    Flows f;
    const double p_l = eval.y[l_], p_v = eval.y[v_], p_x = eval.y[x_];
    const double u = (p_l - p_ref_ + ratio_ * (p_x - p_ref_) - p_set_) / p_ov_;
    const double dp = p_l - p_v;
    f.opening = shape_.opening(u);
    const double g = shape_.orifice(dp), dg = shape_.orifice_slope(dp);
    const double dx_du = shape_.opening_slope(u);
    f.main = c_ * f.opening * g;
    f.dmain_dl = c_ * (dx_du / p_ov_ * g + f.opening * dg);
    f.dmain_dv = -c_ * f.opening * dg;
    f.dmain_dx = c_ * dx_du * ratio_ / p_ov_ * g;
    f.check = check_.flow(p_v - p_l);
    f.dcheck = check_.slope(p_v - p_l);  // d/dp_V; d/dp_L is its negative
    f.leak = leakage_ * dp;
    return f;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const Flows f = flows(eval);
    eval.residual[l_] += f.net();
    eval.residual[v_] -= f.net();
    eval.outputs[q_out_] = f.net();
    eval.outputs[x_out_] = f.opening;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double*) const {
    const Flows f = flows(eval);
    const double dl = f.dmain_dl + leakage_ + f.dcheck;  // d(net)/dp_L
    const double dv = f.dmain_dv - leakage_ - f.dcheck;  // d(net)/dp_V
    const double dx = f.dmain_dx;
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(l_, l_, dl);
    dy.add(l_, v_, dv);
    dy.add(l_, x_, dx);
    dy.add(v_, l_, -dl);
    dy.add(v_, v_, -dv);
    dy.add(v_, x_, -dx);
    return MH_OK;
  }

  // Nothing stored; every path throttles: Q dp >= 0 on each.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const Flows f = flows(eval);
    stored = 0.0;
    dissipation = f.net() * (eval.y[l_] - eval.y[v_]);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  PoppetLaw shape_, check_;
  double p_set_ = 0.0, ratio_ = 0.0, p_ov_ = 1.0, q_nom_ = 0.0, p_nom_ = 1e6, c_ = 0.0;
  double leakage_ = 0.0, p_ref_ = 1e5;
  int32_t l_ = -1, v_ = -1, x_ = -1, q_out_ = -1, x_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor CounterbalanceValve::kDescriptor{
    sizeof(mh_component_descriptor),
    "counterbalance-valve",
    "Counterbalance (over-centre) valve",
    "monohydra",
    "1.0.0",
    "Holds a load at port L: flow L -> V once p_L + pilot_ratio p_X (gauge) exceeds "
    "setting_pressure "
    "(opening over override_pressure; the open valve passes nominal_flow at nominal_pressure, "
    "default 1e6 Pa), free flow V -> L through its check (check_cracking_pressure, default 3e4 "
    "Pa, check_override_pressure, default 2e5 Pa). Options also: leakage (m^3/(s Pa), default "
    "0), reference_pressure (Pa, the drain's, default 1e5; pressures above it open), smoothing "
    "(default 0.1), transition_pressure (Pa, default 2e5). Outputs q (m^3/s, L -> "
    "V) and x (the relief path's opening, 0..1)."};

}  // namespace

const monohydra::SubsystemComponent kCounterbalanceValve =
    monohydra::subsystem_component<CounterbalanceValve>();

}  // namespace hyd
