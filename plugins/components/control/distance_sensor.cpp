// distance-sensor: the distance between two body points and its rate, e.g. a
// cylinder's length and speed (the cylinder's own points), as signal states:
//   s = |p_b - p_a| - offset,   v = e . (v_b - v_a),   e = (p_b - p_a) / |p_b - p_a|
// Both algebraic; their derivatives in the points' motion come from
// coupling_jacobian, and the sensor applies no force.
#include <cmath>

#include "components.hpp"
#include "example_models.hpp"
#include "monohydra/cpp/services.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class DistanceSensor {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kSensorsExample;  // example_models.hpp

  explicit DistanceSensor(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double tol_s = 0.0, tol_v = 0.0;
    if (monohydra::subsystem_setup(h).add_point(h, "a", &a_) != MH_OK ||
        monohydra::subsystem_setup(h).add_point(h, "b", &b_) != MH_OK ||
        finite_option(h, "offset", 0, 0.0, "a finite offset (m)", &offset_) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-9, "a positive length tolerance (m)", &tol_s) !=
            MH_OK ||
        positive_option(h, "speed_tolerance", 0, 1e-7, "a positive speed tolerance (m/s)",
                        &tol_v) != MH_OK)
      return MH_ERROR;
    double pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0};
    if (monohydra::subsystem_setup(h).point_position(h, a_, pa) != MH_OK ||
        monohydra::subsystem_setup(h).point_position(h, b_, pb) != MH_OK)
      return MH_ERROR;
    const double l0 =
        std::sqrt((pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) +
                  (pb[2] - pa[2]) * (pb[2] - pa[2]));
    if (!(l0 > 0.0))
      return monohydra::options(h).option_error(h, "points",
                                                "two points apart at the initial configuration");
    if (add_signal_state(h, "s", "m", l0 - offset_, tol_s, &s_, states_) != MH_OK) return MH_ERROR;
    return add_signal_state(h, "v", "m/s", 0.0, tol_v, &v_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    Geometry g;
    if (!measure(eval, g)) return MH_ERROR;
    eval.residual[s_] += eval.y[s_] - (g.length - offset_);
    eval.residual[v_] += eval.y[v_] - g.rate;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(s_, s_, 1.0);
    dy.add(v_, v_, 1.0);
    return MH_OK;
  }

  // The sensor applies no force: zero blocks (dF_dp, dF_dv).
  mh_status point_force_jacobian(const mh_subsystem_eval&, double*, double*) const { return MH_OK; }

  // dR/dp and dR/dv (n x 6, column-major; row = touched state, column 3b+j =
  // point b's component j); dF/dy, dF/dydot zero.
  mh_status coupling_jacobian(const mh_subsystem_eval& eval, double* dR_dp, double* dR_dv, double*,
                              double*) const {
    Geometry g;
    if (!measure(eval, g)) return MH_ERROR;
    const size_t n = states_.size();
    const size_t rs = states_.local(s_), rv = states_.local(v_);
    const size_t pa = 3 * static_cast<size_t>(a_), pb = 3 * static_cast<size_t>(b_);
    for (size_t j = 0; j < 3; ++j) {
      // s = L: dL/dp_b = e, dL/dp_a = -e (the row is y - L).
      dR_dp[(pa + j) * n + rs] += g.e[j];
      dR_dp[(pb + j) * n + rs] -= g.e[j];
      // v = e . dv: d/dp_b = (dv - e (e . dv)) / L, d/dv_b = e.
      const double transverse = (g.dv[j] - g.e[j] * g.rate) / g.length;
      dR_dp[(pa + j) * n + rv] += transverse;
      dR_dp[(pb + j) * n + rv] -= transverse;
      dR_dv[(pa + j) * n + rv] += g.e[j];
      dR_dv[(pb + j) * n + rv] -= g.e[j];
    }
    return MH_OK;
  }

 private:
  struct Geometry {
    double length = 0.0, rate = 0.0;
    double e[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
  };

  // The points' distance, its unit vector and rate; false (logged) when the
  // points meet, where the direction is undefined.
  bool measure(const mh_subsystem_eval& eval, Geometry& g) const {
    const double* pa = eval.point_p + 3 * a_;
    const double* pb = eval.point_p + 3 * b_;
    const double* va = eval.point_v + 3 * a_;
    const double* vb = eval.point_v + 3 * b_;
    double d[3];
    for (int j = 0; j < 3; ++j) {
      d[j] = pb[j] - pa[j];
      g.dv[j] = vb[j] - va[j];
    }
    g.length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(g.length > 0.0) || !std::isfinite(g.length)) {
      host_->log(host_, MH_LOG_ERROR, "distance-sensor: its points a and b meet");
      return false;
    }
    for (int j = 0; j < 3; ++j) g.e[j] = d[j] / g.length;
    g.rate = g.e[0] * g.dv[0] + g.e[1] * g.dv[1] + g.e[2] * g.dv[2];
    return true;
  }

  const mh_host* host_;
  int32_t a_ = -1, b_ = -1, s_ = -1, v_ = -1;
  double offset_ = 0.0;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor DistanceSensor::kDescriptor{
    sizeof(mh_component_descriptor),
    "distance-sensor",
    "Distance and speed sensor",
    "monohydra",
    "1.0.0",
    "s = |p_b - p_a| - offset (m) and its rate v (m/s) between points a and b (a cylinder's "
    "length and speed with the cylinder's points). Options: offset (m, default 0), tolerance "
    "(m, default 1e-9), speed_tolerance (m/s, default 1e-7). States s, v (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kDistanceSensor =
    monohydra::subsystem_component<DistanceSensor>();

}  // namespace ctl
