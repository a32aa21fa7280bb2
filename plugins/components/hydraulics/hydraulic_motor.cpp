// hydraulic-motor: a rotary motor of displacement D (m^3/rad) between ports A
// and B that drives a revolute joint: the rotor body turns relative to the
// housing body about the joint's axis. The SDK gives subsystems point forces
// only, so the motor's torque is a force couple and its speed is read from
// point velocities. Four points, each pair on one body:
//   housing, rotor         on the axis (distinct): n = (rotor - housing) / |...|
//   housing_arm, rotor_arm off the axis, in the plane normal to n through the
//                          body's axis point: d_k = arm_k - axis_k, w_k = n x d_k
// For a rigid body turning at omega_k, (v_arm - v_axis) . w_k / |w_k|^2 =
// omega_k . n (d_k normal to n), so
//   omega = omega_rotor - omega_housing (rad/s, right-handed about n)
//   T     = D (p_A - p_B) - c_v omega - T_c tanh(omega / omega_s)
//   rotor: +T w_r / |w_r|^2 at rotor_arm, -T w_r / |w_r|^2 at rotor (a pure couple T n)
//   housing: the reaction, -T n, the same way
//   Q     = D omega + C_L (p_A - p_B)      A's row += Q, B's row -= Q
// (flow from A through the motor to B; A at the higher pressure turns the
// rotor positively). Its exact point-force derivatives come from forward-mode
// automatic differentiation of the same expressions (Eigen's AutoDiffScalar).
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>
#include <unsupported/Eigen/AutoDiff>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kPoints = 4;  // housing, rotor, housing_arm, rotor_arm (local indices 0..3)

using Gradient = Eigen::Matrix<double, 6 * kPoints, 1>;  // d/d(12 positions, 12 velocities)
using Dual = Eigen::AutoDiffScalar<Gradient>;

template <class S>
struct Vec {
  S x, y, z;
};
template <class S>
Vec<S> sub(const Vec<S>& a, const Vec<S>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class S>
S dot(const Vec<S>& a, const Vec<S>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class S>
Vec<S> cross(const Vec<S>& a, const Vec<S>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

class HydraulicMotor {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kHydraulicMotorExample;  // example_models.hpp

  explicit HydraulicMotor(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    if (positive_option(h, "displacement", 1, 0.0, "a positive displacement (m^3/rad)",
                        &displacement_) != MH_OK ||
        non_negative(h, "leakage_coefficient", "a non-negative leakage coefficient (m^3/(s Pa))",
                     &leakage_) != MH_OK ||
        non_negative(h, "viscous_friction", "a non-negative viscous friction (N m s/rad)",
                     &viscous_) != MH_OK ||
        non_negative(h, "coulomb_friction", "a non-negative Coulomb friction torque (N m)",
                     &coulomb_) != MH_OK ||
        positive_option(h, "friction_speed", 0, 0.01,
                        "a positive speed (rad/s) over which the Coulomb friction builds up",
                        &omega_s_) != MH_OK)
      return MH_ERROR;
    const char* keys[kPoints] = {"housing", "rotor", "housing_arm", "rotor_arm"};
    double x[kPoints][3];
    for (int i = 0; i < kPoints; ++i) {
      int32_t index = -1;
      if (monohydra::subsystem_setup(h).add_point(h, keys[i], &index) != MH_OK ||
          monohydra::subsystem_setup(h).point_position(h, index, x[i]) != MH_OK)
        return MH_ERROR;
      if (index != i) {
        log_error(h, "hydraulic-motor: unexpected point numbering from the host");
        return MH_ERROR;
      }
    }
    if (check_geometry(x) != MH_OK) return MH_ERROR;
    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &p_a_) != MH_OK) return MH_ERROR;
    states_.add(p_a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &p_b_) != MH_OK) return MH_ERROR;
    states_.add(p_b_);
    const mh_output_spec omega = monohydra::output_spec("omega", "rad/s");
    const mh_output_spec torque = monohydra::output_spec("torque", "N m");
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    if (monohydra::outputs(h).add_output(h, &omega, &omega_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &torque, &torque_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK)
      return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    Vec<double> p[kPoints], v[kPoints];
    load(eval, p, v);
    double f[3 * kPoints];
    double omega = 0.0, torque = 0.0;
    if (!forces(p, v, eval.y[p_a_] - eval.y[p_b_], f, omega, torque)) return degenerate();
    for (int i = 0; i < 3 * kPoints; ++i) eval.point_f[i] += f[i];
    const double q = flow(eval, omega);
    eval.residual[p_a_] += q;
    eval.residual[p_b_] -= q;
    eval.outputs[omega_out_] = omega;
    eval.outputs[torque_out_] = torque;
    eval.outputs[q_out_] = q;
    return MH_OK;
  }

  // The rows depend on the pressures through the leakage only (omega is mechanical).
  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(p_a_, p_a_, leakage_);
    dy.add(p_a_, p_b_, -leakage_);
    dy.add(p_b_, p_a_, -leakage_);
    dy.add(p_b_, p_b_, leakage_);
    return MH_OK;
  }

  // dF/dp and dF/dv (12 x 12 each, column-major), exact by forward-mode AD.
  mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
                                 double* dF_dv) const {
    Vec<Dual> p[kPoints], v[kPoints];
    for (int k = 0; k < kPoints; ++k) {
      Dual* pk[3] = {&p[k].x, &p[k].y, &p[k].z};
      Dual* vk[3] = {&v[k].x, &v[k].y, &v[k].z};
      for (int i = 0; i < 3; ++i) {
        const int j = 3 * k + i;
        *pk[i] = Dual(eval.point_p[j], 6 * kPoints, j);
        *vk[i] = Dual(eval.point_v[j], 6 * kPoints, 3 * kPoints + j);
      }
    }
    Dual f[3 * kPoints];
    Dual omega, torque;
    if (!forces(p, v, Dual(eval.y[p_a_] - eval.y[p_b_]), f, omega, torque)) return degenerate();
    constexpr int n = 3 * kPoints;
    for (int row = 0; row < n; ++row) {
      if (f[row].derivatives().size() == 0) continue;  // a constant (never here)
      for (int col = 0; col < n; ++col) {
        dF_dp[row + n * col] = f[row].derivatives()[col];
        dF_dv[row + n * col] = f[row].derivatives()[n + col];
      }
    }
    return MH_OK;
  }

  // Nothing stored; friction dissipates (c_v omega + T_c tanh) omega >= 0 and the
  // leakage C_L (p_A - p_B)^2 >= 0.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    Vec<double> p[kPoints], v[kPoints];
    load(eval, p, v);
    double f[3 * kPoints];
    double omega = 0.0, torque = 0.0;
    const double dp = eval.y[p_a_] - eval.y[p_b_];
    if (!forces(p, v, dp, f, omega, torque)) return degenerate();
    stored = 0.0;
    dissipation = friction(omega) * omega + leakage_ * dp * dp;
    return MH_OK;
  }

 private:
  static mh_status non_negative(const mh_host* h, const char* key, const char* expected,
                                double* out) {
    if (monohydra::options(h).option_number(h, key, 0, 0.0, out) != MH_OK) return MH_ERROR;
    if (!(std::isfinite(*out) && *out >= 0.0))
      return monohydra::options(h).option_error(h, key, expected);
    return MH_OK;
  }

  // The points must define an axis and two arms normal to it (to 1e-6 of the
  // arm), or omega would not be the joint's rate.
  mh_status check_geometry(const double (&x)[kPoints][3]) const {
    const Vec<double> c_h{x[0][0], x[0][1], x[0][2]}, c_r{x[1][0], x[1][1], x[1][2]};
    const Vec<double> a_h{x[2][0], x[2][1], x[2][2]}, a_r{x[3][0], x[3][1], x[3][2]};
    const Vec<double> axis = sub(c_r, c_h);
    const double length = std::sqrt(dot(axis, axis));
    if (!(length > 1e-9)) {
      log_error(host_,
                "hydraulic-motor: points 'housing' and 'rotor' coincide; place them apart on the "
                "joint's axis (the axis runs from housing to rotor)");
      return MH_ERROR;
    }
    const Vec<double> n{axis.x / length, axis.y / length, axis.z / length};
    const char* names[2] = {"housing_arm", "rotor_arm"};
    const Vec<double> arms[2] = {sub(a_h, c_h), sub(a_r, c_r)};
    for (int k = 0; k < 2; ++k) {
      const double radius = std::sqrt(dot(arms[k], arms[k]));
      const double along = dot(arms[k], n);
      if (!(radius > 1e-9) || std::abs(along) > 1e-6 * radius) {
        log_error(host_, std::string("hydraulic-motor: point '") + names[k] +
                             "' must lie off the axis, in the plane normal to it through '" +
                             (k == 0 ? "housing" : "rotor") + "' (its offset along the axis is " +
                             short_number(along) + " m, its distance " + short_number(radius) +
                             " m)");
        return MH_ERROR;
      }
    }
    return MH_OK;
  }

  mh_status degenerate() const {
    log_error(host_, "hydraulic-motor: the axis or an arm has collapsed (points coincide)");
    return MH_ERROR;
  }

  static void load(const mh_subsystem_eval& eval, Vec<double> (&p)[kPoints],
                   Vec<double> (&v)[kPoints]) {
    for (int k = 0; k < kPoints; ++k) {
      p[k] = {eval.point_p[3 * k], eval.point_p[3 * k + 1], eval.point_p[3 * k + 2]};
      v[k] = {eval.point_v[3 * k], eval.point_v[3 * k + 1], eval.point_v[3 * k + 2]};
    }
  }

  template <class S>
  S friction(const S& omega) const {
    using std::tanh;
    return viscous_ * omega + coulomb_ * tanh(omega / omega_s_);
  }

  // The couple on both bodies at (p, v) for dp = p_A - p_B: f[3k + i] on point k.
  template <class S>
  bool forces(const Vec<S> (&p)[kPoints], const Vec<S> (&v)[kPoints], const S& dp,
              S (&f)[3 * kPoints], S& omega, S& torque) const {
    using std::sqrt;
    const Vec<S> axis = sub(p[1], p[0]);
    const S length = sqrt(dot(axis, axis));
    if (!(length > 1e-12)) return false;
    const Vec<S> n{axis.x / length, axis.y / length, axis.z / length};
    Vec<S> w[2];
    S w2[2];
    S rate[2];
    for (int k = 0; k < 2; ++k) {  // 0: housing (points 0, 2), 1: rotor (points 1, 3)
      const int c = k, a = k + 2;
      w[k] = cross(n, sub(p[a], p[c]));
      w2[k] = dot(w[k], w[k]);
      if (!(w2[k] > 1e-24)) return false;
      rate[k] = dot(sub(v[a], v[c]), w[k]) / w2[k];
    }
    omega = rate[1] - rate[0];
    torque = displacement_ * dp - friction(omega);
    for (int k = 0; k < 2; ++k) {
      const S scale = (k == 1 ? torque : S(-torque)) / w2[k];  // rotor +T, housing -T
      const S arm[3] = {scale * w[k].x, scale * w[k].y, scale * w[k].z};
      for (int i = 0; i < 3; ++i) {
        f[3 * (k + 2) + i] = arm[i];  // at the arm point
        f[3 * k + i] = -arm[i];       // and its opposite at the axis point: a pure couple
      }
    }
    return true;
  }

  double flow(const mh_subsystem_eval& eval, double omega) const {
    return displacement_ * omega + leakage_ * (eval.y[p_a_] - eval.y[p_b_]);
  }

  const mh_host* host_;
  double displacement_ = 0.0;  // m^3/rad
  double leakage_ = 0.0;       // m^3/(s Pa)
  double viscous_ = 0.0;       // N m s/rad
  double coulomb_ = 0.0;       // N m
  double omega_s_ = 0.01;      // rad/s
  int32_t p_a_ = -1, p_b_ = -1, omega_out_ = -1, torque_out_ = -1, q_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor HydraulicMotor::kDescriptor{
    sizeof(mh_component_descriptor),
    "hydraulic-motor",
    "Hydraulic rotary motor",
    "monohydra",
    "1.0.0",
    "Drives a revolute joint: torque D (p_A - p_B) - c_v omega - T_c tanh(omega/omega_s) as a "
    "force couple on the rotor (reaction on the housing), flow D omega + C_L (p_A - p_B) from A "
    "to B. Points housing and rotor (on the axis, apart; the axis runs from housing to rotor), "
    "housing_arm and rotor_arm (off the axis, normal to it). Options: displacement (m^3/rad), "
    "leakage_coefficient (m^3/(s Pa), default 0), viscous_friction (N m s/rad, default 0), "
    "coulomb_friction (N m, default 0), friction_speed (rad/s, default 0.01). Outputs omega "
    "(rad/s), torque (N m), q (m^3/s)."};

}  // namespace

const monohydra::SubsystemComponent kHydraulicMotor =
    monohydra::subsystem_component<HydraulicMotor>();

}  // namespace hyd
