// cylinder: a double-acting hydraulic cylinder (Eqs. 28-29, 42-45) between
// point a (the housing end) and point b (the rod end). With s = |p_b - p_a|,
// sdot = ds/dt (> 0 extending), s0 = s at the initial configuration:
//   l2 = l2_0 + (s - s0), l3 = l3_0 - (s - s0),  l2_0 = s0 - l, l3_0 = l - l2_0
//   (the case study's Decision on the sign of Eq. 43)
//   A's row += A2 l2 (1/B_oil + 1/B_c) dp_A/dt + A2 sdot   (chamber storage; the
//   B's row += A3 l3 (1/B_oil + 1/B_c) dp_B/dt - A3 sdot    piston's Eq. 28 flows)
//   F = p_A A2 - p_B A3 - F_mu                               (Eq. 29)
//   F_mu = (1 - eta) |p_A A2 - p_B A3| tanh(sdot / v_s)      (the Decision on friction)
// +F e on point b and -F e on point a, e the unit vector from a to b.
// Optional (off by default): end stops at the stroke ends (end_stop.hpp) and a
// minimum-pressure limit in both chambers (gas_release.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "components.hpp"
#include "end_stop.hpp"
#include "example_models.hpp"
#include "gas_release.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/visual.h"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

class Cylinder {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kCylinderExample;  // example_models.hpp

  explicit Cylinder(const mh_host* host) : host_(host) {}

  // Changed in place (parameters.h): the areas and the compliance follow.
  // A rod diameter that would reach the piston's is refused.
  static constexpr monohydra::ParameterSpec kParameters[] = {
      {"piston_diameter", "m", monohydra::kPositive, HUGE_VAL},
      {"rod_diameter", "m", monohydra::kPositive, HUGE_VAL},
      {"chamber_bulk_modulus", "Pa", monohydra::kPositive, HUGE_VAL},
      {"fluid_bulk_modulus", "Pa", monohydra::kPositive, HUGE_VAL},
      {"efficiency", "1", monohydra::kPositive, 1.0},
      {"friction_velocity", "m/s", monohydra::kPositive, HUGE_VAL}};
  double parameter(uint32_t index) const {
    switch (index) {
      case 0:
        return d2_;
      case 1:
        return d3_;
      case 2:
        return chamber_;
      case 3:
        return fluid_;
      case 4:
        return efficiency_;
      default:
        return v_s_;
    }
  }
  void set_parameter(uint32_t index, double value) {
    const double d2 = index == 0 ? value : d2_, d3 = index == 1 ? value : d3_;
    if (!(d3 < d2))
      throw std::invalid_argument("a rod diameter of " + short_number(d3) +
                                  " m would not be below the piston diameter " + short_number(d2) +
                                  " m");
    d2_ = d2;
    d3_ = d3;
    if (index == 2) chamber_ = value;
    if (index == 3) fluid_ = value;
    if (index == 4) efficiency_ = value;
    if (index == 5) v_s_ = value;
    derive();
  }

  mh_status setup() {
    const mh_host* h = host_;
    double d2 = 0.0, d3 = 0.0, chamber = 0.0, fluid = 0.0;
    if (positive_option(h, "piston_diameter", 1, 0.0, "a positive piston diameter (m)", &d2) !=
            MH_OK ||
        positive_option(h, "rod_diameter", 1, 0.0, "a positive rod diameter (m)", &d3) != MH_OK ||
        positive_option(h, "length", 1, 0.0, "a positive cylinder length (m)", &length_) != MH_OK ||
        positive_option(h, "chamber_bulk_modulus", 1, 0.0,
                        "a positive bulk modulus of the cylinder (Pa)", &chamber) != MH_OK ||
        positive_option(h, "fluid_bulk_modulus", 1, 0.0,
                        "a positive bulk modulus of the fluid (Pa)", &fluid) != MH_OK ||
        monohydra::options(h).option_number(h, "efficiency", 1, 0.0, &efficiency_) != MH_OK ||
        positive_option(h, "friction_velocity", 0, 0.01, "a positive friction velocity (m/s)",
                        &v_s_) != MH_OK)
      return MH_ERROR;
    if (!(d3 < d2))
      return monohydra::options(h).option_error(
          h, "rod_diameter",
          ("a rod diameter below the piston diameter " + short_number(d2) + " m").c_str());
    if (!(efficiency_ > 0.0 && efficiency_ <= 1.0))
      return monohydra::options(h).option_error(h, "efficiency", "an efficiency in (0, 1]");
    d2_ = d2;
    d3_ = d3;
    chamber_ = chamber;
    fluid_ = fluid;
    derive();

    double xa[3], xb[3];
    if (monohydra::subsystem_setup(h).add_point(h, "a", &point_a_) != MH_OK ||
        monohydra::subsystem_setup(h).add_point(h, "b", &point_b_) != MH_OK ||
        monohydra::subsystem_setup(h).point_position(h, point_a_, xa) != MH_OK ||
        monohydra::subsystem_setup(h).point_position(h, point_b_, xb) != MH_OK)
      return MH_ERROR;
    s0_ = std::sqrt((xb[0] - xa[0]) * (xb[0] - xa[0]) + (xb[1] - xa[1]) * (xb[1] - xa[1]) +
                    (xb[2] - xa[2]) * (xb[2] - xa[2]));
    l2_0_ = s0_ - length_;
    l3_0_ = length_ - l2_0_;
    if (l2_0_ < 0.0 || l3_0_ < 0.0)
      return monohydra::options(h).option_error(
          h, "length",
          ("a cylinder length l with s0/2 <= l <= s0, where s0 = " + short_number(s0_) +
           " m is the initial distance between points a and b (the chambers l2_0 = s0 - l = " +
           short_number(l2_0_) + " m and l3_0 = l - l2_0 = " + short_number(l3_0_) +
           " m must not be negative)")
              .c_str());

    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &p_a_) != MH_OK) return MH_ERROR;
    states_.add(p_a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &p_b_) != MH_OK) return MH_ERROR;
    states_.add(p_b_);
    const mh_output_spec s = monohydra::output_spec("s", "m");
    const mh_output_spec sdot = monohydra::output_spec("sdot", "m/s");
    const mh_output_spec force = monohydra::output_spec("Fs", "N");
    if (monohydra::outputs(h).add_output(h, &s, &s_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &sdot, &sdot_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &force, &force_out_) != MH_OK)
      return MH_ERROR;
    if (setup_end_stop() != MH_OK) return MH_ERROR;
    if (setup_gas_release() != MH_OK) return MH_ERROR;
    return declare_look(d2, d3);
  }

  // For a host that draws the run: a barrel of the cylinder's length from
  // point a, its tube a fifth wider than the piston, the rod from point b; the
  // cap chamber coloured by A's pressure, the rod chamber by B's.
  mh_status declare_look(double piston_diameter, double rod_diameter) const {
    const auto* visual =
        static_cast<const mh_visual_service*>(host_->get_service(host_, MH_SERVICE_VISUAL));
    if (visual == nullptr) return MH_OK;
    mh_visual_spec look{};
    look.struct_size = sizeof(mh_visual_spec);
    look.kind = MH_VISUAL_ACTUATOR;
    look.point_a = point_a_;
    look.point_b = point_b_;
    look.barrel_length = length_;
    look.barrel_diameter = 1.2 * piston_diameter;
    look.rod_diameter = rod_diameter;
    look.state_a = p_a_;
    look.state_b = p_b_;
    return visual->add_visual(host_, &look);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    State st;
    if (!measure(eval, st)) return MH_ERROR;
    const double p_a = eval.y[p_a_], p_b = eval.y[p_b_];
    // Chamber storage (Eq. 23's V_s / B_oil + V_s / B_c) and the piston's flows (Eq. 28).
    eval.residual[p_a_] += a2_ * st.l2 * compliance_ * eval.ydot[p_a_] + a2_ * st.sdot;
    eval.residual[p_b_] += a3_ * st.l3 * compliance_ * eval.ydot[p_b_] - a3_ * st.sdot;
    if (gas_a_.on()) {  // the chambers' released gas (gas_release.hpp)
      eval.residual[p_a_] += gas_a_.capacitance(p_a) * eval.ydot[p_a_];
      eval.residual[p_b_] += gas_b_.capacitance(p_b) * eval.ydot[p_b_];
    }
    const double force = p_a * a2_ - p_b * a3_ - friction(p_a, p_b, st.sdot);  // Eq. 29
    const double pushed = end_stop_.on() ? force + stop_force(eval, st) : force;
    for (int i = 0; i < 3; ++i) {
      eval.point_f[3 * point_a_ + i] -= pushed * st.e[i];
      eval.point_f[3 * point_b_ + i] += pushed * st.e[i];
    }
    eval.outputs[s_out_] = st.s;
    eval.outputs[sdot_out_] = st.sdot;
    eval.outputs[force_out_] = force;
    return MH_OK;
  }

  // The rows depend on the pressures only through their rates.
  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    State st;
    if (!measure(eval, st)) return MH_ERROR;
    monohydra::JacobianBlock dydot(states_, d_dydot);
    dydot.add(p_a_, p_a_, a2_ * st.l2 * compliance_);
    dydot.add(p_b_, p_b_, a3_ * st.l3 * compliance_);
    if (gas_a_.on()) gas_jacobian(eval, d_dy, d_dydot);
    return MH_OK;
  }

  // d(point forces)/d(points' positions, velocities), states held:
  // 3P x 3P column-major. With f_b = F e = -f_a, de/dx_b = (I - e e^T)/s and
  // dsdot/dx_b = (v_b - v_a)^T (I - e e^T)/s, dsdot/dv_b = e^T (minus for a).
  mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
                                 double* dF_dv) const {
    Motion mo;
    if (!motion(eval, mo)) return MH_ERROR;
    const size_t n3 = 3 * eval.num_points;
    for (int side = 0; side < 2; ++side) {
      const int32_t force_point = side == 0 ? point_a_ : point_b_;
      const double fs = side == 0 ? -1.0 : 1.0;  // f_a = -F e, f_b = +F e
      for (int k = 0; k < 2; ++k) {
        const int32_t moved = k == 0 ? point_a_ : point_b_;
        const double ms = k == 0 ? -1.0 : 1.0;  // d/dx_a = -d/dx_b
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const size_t at = (3 * static_cast<size_t>(moved) + static_cast<size_t>(j)) * n3 +
                              3 * static_cast<size_t>(force_point) + static_cast<size_t>(i);
            dF_dp[at] += fs * ms *
                         (mo.st.e[i] * (mo.dF_ds * mo.st.e[j] + mo.dF_dsdot * mo.dsdot_dxb[j]) +
                          mo.force * mo.de_dxb[i][j]);
            dF_dv[at] += fs * ms * mo.st.e[i] * mo.dF_dsdot * mo.st.e[j];
          }
      }
    }
    return MH_OK;
  }

  // The coupling to the mechanics: rows by the points' motion (n x 3P) and
  // point forces by the pressures (3P x n), both column-major.
  mh_status coupling_jacobian(const mh_subsystem_eval& eval, double* dR_dp, double* dR_dv,
                              double* dF_dy, double*) const {
    Motion mo;
    if (!motion(eval, mo)) return MH_ERROR;
    const size_t n3 = 3 * eval.num_points;  // rows of dF_dy
    const size_t nt = eval.num_touched;     // rows of dR_dp, dR_dv
    const size_t ra = states_.local(p_a_), rb = states_.local(p_b_);
    // d(A row)/ds through l2 and d(B row)/ds through l3 = -s; past an end
    // stop a chamber's length is held at 0 and no longer moves with s.
    const bool a_free = !end_stop_.on() || l2_0_ + (mo.st.s - s0_) > 0.0;
    const bool b_free = !end_stop_.on() || l3_0_ - (mo.st.s - s0_) > 0.0;
    const double ga = a_free ? a2_ * compliance_ * eval.ydot[p_a_] : 0.0;
    const double gb = b_free ? -a3_ * compliance_ * eval.ydot[p_b_] : 0.0;
    for (int k = 0; k < 2; ++k) {
      const int32_t moved = k == 0 ? point_a_ : point_b_;
      const double ms = k == 0 ? -1.0 : 1.0;
      for (int j = 0; j < 3; ++j) {
        const size_t c = 3 * static_cast<size_t>(moved) + static_cast<size_t>(j);
        const double ds = ms * mo.st.e[j];
        const double dsdot_dx = ms * mo.dsdot_dxb[j];
        const double dsdot_dv = ms * mo.st.e[j];
        dR_dp[c * nt + ra] += ga * ds + a2_ * dsdot_dx;
        dR_dp[c * nt + rb] += gb * ds - a3_ * dsdot_dx;
        dR_dv[c * nt + ra] += a2_ * dsdot_dv;
        dR_dv[c * nt + rb] += -a3_ * dsdot_dv;
      }
    }
    // dF/dp_A, dF/dp_B of F = p_A A2 - p_B A3 - F_mu, along e (b) and -e (a).
    const double g = eval.y[p_a_] * a2_ - eval.y[p_b_] * a3_;
    const double sign = g > 0.0 ? 1.0 : (g < 0.0 ? -1.0 : 0.0);
    const double th = std::tanh(mo.st.sdot / v_s_);
    const double dF_dpa = a2_ * (1.0 - (1.0 - efficiency_) * sign * th);
    const double dF_dpb = -a3_ * (1.0 - (1.0 - efficiency_) * sign * th);
    for (int side = 0; side < 2; ++side) {
      const size_t pt = static_cast<size_t>(side == 0 ? point_a_ : point_b_);
      const double fs = side == 0 ? -1.0 : 1.0;
      for (size_t i = 0; i < 3; ++i) {
        dF_dy[ra * n3 + 3 * pt + i] += fs * dF_dpa * mo.st.e[i];
        dF_dy[rb * n3 + 3 * pt + i] += fs * dF_dpb * mo.st.e[i];
      }
    }
    return MH_OK;
  }

  // Nothing stored (the fluid's compression energy is not tracked); the seals
  // dissipate F_mu sdot >= 0.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    State st;
    if (!measure(eval, st)) return MH_ERROR;
    stored = 0.0;
    dissipation = friction(eval.y[p_a_], eval.y[p_b_], st.sdot) * st.sdot;
    if (end_stop_.on()) {  // the stops' spring energy and damping
      double stop_stored = 0.0, stop_dissipation = 0.0;
      end_stop_.energy(st.s, st.sdot, stop_stored, stop_dissipation);
      stored += stop_stored;
      dissipation += stop_dissipation;
    }
    return MH_OK;
  }

 private:
  struct State {
    double s = 0.0, sdot = 0.0;     // m, m/s
    double e[3] = {0.0, 0.0, 0.0};  // unit vector from a to b
    double l2 = 0.0, l3 = 0.0;      // chamber lengths, m
  };

  // Geometry at `eval`; false (after logging) when the points coincide or the
  // stroke left the cylinder.
  bool measure(const mh_subsystem_eval& eval, State& st) const {
    const double* xa = eval.point_p + 3 * point_a_;
    const double* xb = eval.point_p + 3 * point_b_;
    const double* va = eval.point_v + 3 * point_a_;
    const double* vb = eval.point_v + 3 * point_b_;
    const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
    st.s = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(st.s > 1e-12)) {
      log_error(host_, "the cylinder's points a and b coincide: no direction");
      return false;
    }
    st.sdot = 0.0;
    for (int i = 0; i < 3; ++i) {
      st.e[i] = d[i] / st.s;
      st.sdot += (vb[i] - va[i]) * st.e[i];
    }
    st.l2 = l2_0_ + (st.s - s0_);
    st.l3 = l3_0_ - (st.s - s0_);
    if (end_stop_.on()) {  // past a stop the chamber is empty, not negative
      st.l2 = std::max(st.l2, 0.0);
      st.l3 = std::max(st.l3, 0.0);
    }
    if (st.l2 < 0.0 || st.l3 < 0.0) {
      log_error(host_, "the stroke left the cylinder: actuator length s = " + short_number(st.s) +
                           " m is outside its range [s0 - l2_0, s0 + l3_0] = [" +
                           short_number(s0_ - l2_0_) + ", " + short_number(s0_ + l3_0_) + "] m");
      return false;
    }
    return true;
  }

  // End stops (end_stop.hpp) from end_stop_stiffness (which turns them on),
  // end_stop_damping and end_stop_depth, at the stroke ends s = l and s = 2 l
  // (a chamber length 0); with them on, the cylinder also writes F_stop.
  mh_status setup_end_stop() {
    const mh_host* h = host_;
    double k = kNaN, c = kNaN, depth = kNaN;
    if (monohydra::options(h).option_number(h, "end_stop_stiffness", 0, kNaN, &k) != MH_OK ||
        monohydra::options(h).option_number(h, "end_stop_damping", 0, kNaN, &c) != MH_OK ||
        monohydra::options(h).option_number(h, "end_stop_depth", 0, kNaN, &depth) != MH_OK)
      return MH_ERROR;
    if (std::isnan(k)) {
      if (!std::isnan(c))
        return monohydra::options(h).option_error(
            h, "end_stop_damping", "end_stop_stiffness beside it (the stops are off without it)");
      if (!std::isnan(depth))
        return monohydra::options(h).option_error(
            h, "end_stop_depth", "end_stop_stiffness beside it (the stops are off without it)");
      return MH_OK;
    }
    if (!(k > 0.0))
      return monohydra::options(h).option_error(h, "end_stop_stiffness",
                                                "a positive stiffness (N/m)");
    if (std::isnan(c)) c = 0.0;
    if (!(c >= 0.0))
      return monohydra::options(h).option_error(h, "end_stop_damping",
                                                "a non-negative damping (N s/m)");
    if (std::isnan(depth)) depth = 1e-3;
    if (!(depth > 0.0))
      return monohydra::options(h).option_error(
          h, "end_stop_depth", "a positive depth (m) over which the stop's damping comes in");
    end_stop_ = EndStop(s0_ - l2_0_, s0_ + l3_0_, k, c, depth);
    const mh_output_spec f = monohydra::output_spec("F_stop", "N");
    return monohydra::outputs(h).add_output(h, &f, &stop_out_);
  }
  // The chambers' minimum-pressure limit (gas_release.hpp), its gas fraction
  // taken of each chamber's full-stroke volume, A2 l and A3 l.
  mh_status setup_gas_release() {
    GasRelease gas;
    if (gas.read(host_) != MH_OK) return MH_ERROR;
    gas_a_ = gas.for_volume(a2_ * length_);
    gas_b_ = gas.for_volume(a3_ * length_);
    return MH_OK;
  }
  void gas_jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    monohydra::JacobianBlock dy(states_, d_dy), dydot(states_, d_dydot);
    const double p_a = eval.y[p_a_], p_b = eval.y[p_b_];
    dydot.add(p_a_, p_a_, gas_a_.capacitance(p_a));
    dydot.add(p_b_, p_b_, gas_b_.capacitance(p_b));
    dy.add(p_a_, p_a_, gas_a_.capacitance_slope(p_a) * eval.ydot[p_a_]);
    dy.add(p_b_, p_b_, gas_b_.capacitance_slope(p_b) * eval.ydot[p_b_]);
  }

  double stop_force(const mh_subsystem_eval& eval, const State& st) const {
    const double f = end_stop_.force(st.s, st.sdot);
    eval.outputs[stop_out_] = f;
    return f;
  }

  // The geometry and the force's derivatives in it, for the Jacobians.
  struct Motion {
    State st;
    double force = 0.0;               // F of Eq. 29, with the end stops' force
    double dF_ds = 0.0;               // of the end stops
    double dF_dsdot = 0.0;            // of the friction and the end stops' damping
    double de_dxb[3][3] = {};         // (I - e e^T) / s
    double dsdot_dxb[3] = {0, 0, 0};  // (v_b - v_a)^T (I - e e^T) / s
  };

  bool motion(const mh_subsystem_eval& eval, Motion& mo) const {
    if (!measure(eval, mo.st)) return false;
    const double p_a = eval.y[p_a_], p_b = eval.y[p_b_];
    mo.force = p_a * a2_ - p_b * a3_ - friction(p_a, p_b, mo.st.sdot);
    const double th = std::tanh(mo.st.sdot / v_s_);
    mo.dF_dsdot = -(1.0 - efficiency_) * std::abs(p_a * a2_ - p_b * a3_) * (1.0 - th * th) / v_s_;
    if (end_stop_.on()) {
      double stop_ds = 0.0, stop_dsdot = 0.0;
      mo.force += end_stop_.force(mo.st.s, mo.st.sdot, &stop_ds, &stop_dsdot);
      mo.dF_ds = stop_ds;
      mo.dF_dsdot += stop_dsdot;
    }
    const double* va = eval.point_v + 3 * point_a_;
    const double* vb = eval.point_v + 3 * point_b_;
    for (int i = 0; i < 3; ++i) {
      mo.dsdot_dxb[i] = 0.0;
      for (int j = 0; j < 3; ++j) {
        mo.de_dxb[i][j] = ((i == j ? 1.0 : 0.0) - mo.st.e[i] * mo.st.e[j]) / mo.st.s;
      }
    }
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) mo.dsdot_dxb[j] += (vb[i] - va[i]) * mo.de_dxb[i][j];
    return true;
  }

  double friction(double p_a, double p_b, double sdot) const {
    return (1.0 - efficiency_) * std::abs(p_a * a2_ - p_b * a3_) * std::tanh(sdot / v_s_);
  }

  const mh_host* host_;
  double length_ = 0.0, efficiency_ = 1.0, v_s_ = 0.01;
  double a2_ = 0.0, a3_ = 0.0;                                // piston and rod side areas, m^2
  double compliance_ = 0.0;                                   // 1/B_oil + 1/B_c, 1/Pa
  double d2_ = 0.0, d3_ = 0.0, chamber_ = 0.0, fluid_ = 0.0;  // the options they derive from

  void derive() {
    a2_ = 0.25 * kPi * d2_ * d2_;
    a3_ = 0.25 * kPi * (d2_ * d2_ - d3_ * d3_);
    compliance_ = 1.0 / fluid_ + 1.0 / chamber_;
  }
  double s0_ = 0.0, l2_0_ = 0.0, l3_0_ = 0.0;
  int32_t point_a_ = 0, point_b_ = 1;
  int32_t p_a_ = -1, p_b_ = -1, s_out_ = -1, sdot_out_ = -1, force_out_ = -1;
  EndStop end_stop_;          // off unless end_stop_stiffness is given
  GasRelease gas_a_, gas_b_;  // off unless minimum_pressure is given
  int32_t stop_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Cylinder::kDescriptor{
    sizeof(mh_component_descriptor),
    "cylinder",
    "Double-acting hydraulic cylinder",
    "monohydra",
    "1.0.0",
    "Between points a (housing) and b (rod end); ports A (piston side) and B (rod side). "
    "Force p_A A2 - p_B A3 - F_mu pushes a and b apart (Eq. 29); chambers A2 l2 and A3 l3 store "
    "fluid, the piston displaces A2 sdot and A3 sdot (Eq. 28). Options: piston_diameter (m), "
    "rod_diameter (m), length (m), chamber_bulk_modulus (Pa), fluid_bulk_modulus (Pa), "
    "efficiency (0..1], friction_velocity (m/s, default 0.01); end stops (off by default): "
    "end_stop_stiffness (N/m), end_stop_damping (N s/m, default 0), end_stop_depth (m, default "
    "1e-3); cavitation limit (off by default): minimum_pressure (Pa), gas_fraction (default "
    "1e-3), gas_reference_pressure (Pa, default 1e5). Outputs s (m), sdot (m/s), Fs (N), and "
    "F_stop (N) with end stops."};

}  // namespace

const monohydra::SubsystemComponent kCylinder = monohydra::subsystem_component<Cylinder>();

}  // namespace hyd
