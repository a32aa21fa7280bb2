// pilot-check-valve: a pilot-operated check valve. Free flow from port A to
// port B once p_A - p_B exceeds the spring's cracking pressure; reverse flow
// B -> A only when the pilot (port X) lifts the poppet: a pilot piston of R
// times the seat's area pushes it open when R p_X exceeds p_B - p_A plus the
// spring. Both are one force balance on the poppet, so one opening serves:
//   u = (p_A - p_B + R (p_X - p_ref) - p_cr) / p_ov,  x = r(u) - r(u - 1)
//   (pressure_valve.hpp; p_ref the drain's pressure the pilot piston's back
//   sees, 1e5 Pa by default)
//   Q = C x g(p_A - p_B)  (A -> B; negative when the pilot lets B flow back)
//   C = Q_nom / g(p_nom)  (fully open: Q_nom at the drop p_nom)
//   A's row += Q,  B's row -= Q; X takes no flow (its piston's volume is left out).
// With p_X = 0 it is a check valve; holding a load at B it is shut until
// p_X - p_ref = (p_B - p_A + p_cr) / R. Source: docs/hydraulics.md.
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "pressure_valve.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class PilotCheckValve {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kPilotCheckValveExample;

  explicit PilotCheckValve(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double smoothing = 0.0, p_tr = 0.0, q_nom = 0.0, p_nom = 0.0;
    if (monohydra::options(h).option_number(h, "cracking_pressure", 0, 3e4, &p_cr_) != MH_OK ||
        monohydra::options(h).option_number(h, "reference_pressure", 0, 1e5, &p_ref_) != MH_OK)
      return MH_ERROR;
    if (!(p_cr_ >= 0.0))
      return monohydra::options(h).option_error(h, "cracking_pressure",
                                                "a non-negative cracking pressure (Pa)");
    if (positive_option(h, "pilot_ratio", 1, 0.0, "a positive pilot ratio (e.g. 3 to 5)",
                        &ratio_) != MH_OK ||
        positive_option(h, "override_pressure", 0, 5e5,
                        "a positive override (Pa): the rise of the opening pressure from "
                        "cracking to fully open",
                        &p_ov_) != MH_OK ||
        positive_option(h, "nominal_flow", 1, 0.0, "a positive nominal flow (m^3/s)", &q_nom) !=
            MH_OK ||
        positive_option(h, "nominal_pressure", 0, 5e5,
                        "a positive pressure drop (Pa) at which the open valve passes nominal_flow",
                        &p_nom) != MH_OK ||
        read_poppet_shape(h, &smoothing, &p_tr) != MH_OK)
      return MH_ERROR;
    shape_ = PoppetLaw(0.0, 1.0, smoothing, p_tr);
    c_ = q_nom / shape_.orifice(p_nom);
    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &a_) != MH_OK) return MH_ERROR;
    states_.add(a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &b_) != MH_OK) return MH_ERROR;
    states_.add(b_);
    if (add_hydraulic_port(h, "X", MH_PORT_FLOW, kNaN, kNaN, &x_) != MH_OK) return MH_ERROR;
    states_.add(x_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    const mh_output_spec opening = monohydra::output_spec("x", "");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &opening, &x_out_) != MH_OK)
      return MH_ERROR;
    return MH_OK;
  }

  struct Flow {
    double opening = 0.0, q = 0.0, dq_da = 0.0, dq_db = 0.0, dq_dx = 0.0;
  };
  Flow flow(const mh_subsystem_eval& eval) const {
    Flow f;
    const double dp = eval.y[a_] - eval.y[b_];
    const double u = (dp + ratio_ * (eval.y[x_] - p_ref_) - p_cr_) / p_ov_;
    f.opening = shape_.opening(u);
    const double g = shape_.orifice(dp), dg = shape_.orifice_slope(dp);
    const double dx_du = shape_.opening_slope(u);
    f.q = c_ * f.opening * g;
    f.dq_da = c_ * (dx_du / p_ov_ * g + f.opening * dg);
    f.dq_db = -f.dq_da;
    f.dq_dx = c_ * dx_du * ratio_ / p_ov_ * g;
    return f;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const Flow f = flow(eval);
    eval.residual[a_] += f.q;
    eval.residual[b_] -= f.q;
    eval.outputs[q_out_] = f.q;
    eval.outputs[x_out_] = f.opening;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double*) const {
    const Flow f = flow(eval);
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(a_, a_, f.dq_da);
    dy.add(a_, b_, f.dq_db);
    dy.add(a_, x_, f.dq_dx);
    dy.add(b_, a_, -f.dq_da);
    dy.add(b_, b_, -f.dq_db);
    dy.add(b_, x_, -f.dq_dx);
    return MH_OK;
  }

  // Nothing stored; Q has the sign of p_A - p_B (g is odd), so Q dp >= 0.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    stored = 0.0;
    dissipation = flow(eval).q * (eval.y[a_] - eval.y[b_]);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  PoppetLaw shape_;
  double p_cr_ = 0.0, ratio_ = 0.0, p_ov_ = 1.0, c_ = 0.0, p_ref_ = 1e5;
  int32_t a_ = -1, b_ = -1, x_ = -1, q_out_ = -1, x_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor PilotCheckValve::kDescriptor{
    sizeof(mh_component_descriptor),
    "pilot-check-valve",
    "Pilot-operated check valve",
    "monohydra",
    "1.0.0",
    "Free flow A -> B above cracking_pressure (default 3e4 Pa); reverse flow B -> A once "
    "pilot_ratio (p_X - reference_pressure) exceeds p_B - p_A + cracking_pressure. Opens over "
    "override_pressure "
    "(default 5e5 Pa); the open valve passes nominal_flow at nominal_pressure (default 5e5 Pa). "
    "Options also: reference_pressure (Pa, the drain's the pilot works against, default 1e5), "
    "smoothing (default 0.1), transition_pressure (Pa, default 2e5). Outputs q "
    "(m^3/s, A -> B) and x (the opening, 0..1)."};

}  // namespace

const monohydra::SubsystemComponent kPilotCheckValve =
    monohydra::subsystem_component<PilotCheckValve>();

}  // namespace hyd
