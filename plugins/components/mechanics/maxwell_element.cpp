// A Maxwell element between two body points: a spring k in series with a
// damper c. The damper's elongation delta is a state of the element, so it
// exercises states, body forces and their coupled tangent through the ABI:
//   tension   T = k (l - l0 - delta) = c ddelta/dt
//   residual  c ddelta/dt - k (l - l0 - delta) = 0   (row of delta)
#include "components.hpp"
#include "example_models.hpp"
#include "monohydra/cpp/services.hpp"
#include "point_pair.hpp"

namespace mech {
namespace {

class Maxwell {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kSliderExample;  // example_models.hpp

  explicit Maxwell(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double delta0 = 0.0;
    mh_mech_info info{};
    info.struct_size = sizeof(info);
    if (monohydra::mechanism(h).mech_info(h, &info) != MH_OK) return MH_ERROR;
    double tol = info.position_tolerance;
    if (monohydra::options(h).option_number(h, "stiffness", 1, 0.0, &k_) != MH_OK ||
        monohydra::options(h).option_number(h, "damping", 1, 0.0, &c_) != MH_OK ||
        monohydra::options(h).option_number(h, "free_length", 1, 0.0, &l0_) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_elongation", 0, 0.0, &delta0) != MH_OK ||
        monohydra::options(h).option_number(h, "tolerance", 0, tol, &tol) != MH_OK)
      return MH_ERROR;
    if (!(k_ > 0.0))
      return monohydra::options(h).option_error(h, "stiffness", "a positive stiffness (N/m)");
    if (!(c_ > 0.0))
      return monohydra::options(h).option_error(h, "damping", "a positive damping (N s/m)");
    if (l0_ < 0.0)
      return monohydra::options(h).option_error(h, "free_length", "a non-negative length (m)");
    if (!(tol > 0.0))
      return monohydra::options(h).option_error(h, "tolerance", "a positive tolerance (m)");
    int32_t a = -1, b = -1;
    const mh_state_spec delta = monohydra::state_spec("delta", "m", delta0, tol);
    if (monohydra::subsystem_setup(h).add_point(h, "a", &a) != MH_OK ||
        monohydra::subsystem_setup(h).add_point(h, "b", &b) != MH_OK ||
        monohydra::subsystem_setup(h).add_state(h, &delta, &delta_) != MH_OK)
      return MH_ERROR;
    return declare_link(h, a, b);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    PointPair pp;
    if (!pp.measure(&eval)) {
      host_->log(host_, MH_LOG_ERROR, "the Maxwell element's points coincide: no direction");
      return MH_ERROR;
    }
    const double delta = eval.y[delta_];
    const double tension = k_ * (pp.length - l0_ - delta);
    eval.residual[delta_] += c_ * eval.ydot[delta_] - tension;
    pp.apply_tension(&eval, tension);
    return MH_OK;
  }

  // Touched states: only delta, so 1 x 1 blocks.
  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double* d_dydot) const {
    d_dy[0] = k_;
    d_dydot[0] = c_;
    return MH_OK;
  }

  // T = k (l - l0 - delta): the point forces' derivatives, and the
  // coupling: delta's row c deltadot - T by the points' motion
  // (-k dl/dp), the forces by delta (dT/ddelta = -k; +T e on a, -T e on b).
  mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
                                 double* dF_dv) const {
    PointPair pp;
    if (!pp.measure(&eval)) return MH_DISCARD;
    pp.tension_jacobian(&eval, k_ * (pp.length - l0_ - eval.y[delta_]), k_, 0.0, dF_dp, dF_dv);
    return MH_OK;
  }
  mh_status coupling_jacobian(const mh_subsystem_eval& eval, double* dR_dp, double*, double* dF_dy,
                              double*) const {
    PointPair pp;
    if (!pp.measure(&eval)) return MH_DISCARD;
    for (int j = 0; j < 3; ++j) {
      dR_dp[j] += k_ * pp.e[j];       // point a: dl/dp_a = -e
      dR_dp[3 + j] -= k_ * pp.e[j];   // point b: dl/dp_b = e
      dF_dy[j] += -k_ * pp.e[j];      // on a: +T e
      dF_dy[3 + j] -= -k_ * pp.e[j];  // on b: -T e
    }
    return MH_OK;
  }

  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    PointPair pp;
    if (!pp.measure(&eval)) return MH_DISCARD;
    const double spring = pp.length - l0_ - eval.y[delta_];
    const double rate = eval.ydot[delta_];
    stored = 0.5 * k_ * spring * spring;
    dissipation = c_ * rate * rate;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double k_ = 0.0, c_ = 0.0, l0_ = 0.0;
  int32_t delta_ = -1;  // global state index
};

const mh_component_descriptor Maxwell::kDescriptor{
    sizeof(mh_component_descriptor),
    "maxwell",
    "Maxwell element",
    "monohydra",
    "1.0.0",
    "Spring in series with a damper between points a and b; state delta (m) is the damper's "
    "elongation. Options: stiffness (N/m), damping (N s/m), free_length (m), "
    "initial_elongation (m, default 0), tolerance (m)."};

}  // namespace

const monohydra::SubsystemComponent kMaxwell = monohydra::subsystem_component<Maxwell>();

}  // namespace mech
