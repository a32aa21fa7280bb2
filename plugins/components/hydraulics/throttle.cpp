// throttle: a fixed orifice between nodes a and b (Eqs. 24-25):
//   C_vt = C_d A sqrt(2 / rho),   Q_ab = C_vt g(p_a - p_b)   (orifice_flow.hpp)
//   a's row += Q_ab (leaves a),   b's row -= Q_ab (enters b)
#include <array>
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "orifice_flow.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class Throttle {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kThrottleExample;  // example_models.hpp

  explicit Throttle(const mh_host* host) : host_(host) {}

  // Changed in place (parameters.h): C_vt of Eq. 25 follows.
  static constexpr monohydra::ParameterSpec kParameters[] = {
      {"area", "m^2", monohydra::kPositive, HUGE_VAL},
      {"discharge_coefficient", "1", monohydra::kPositive, HUGE_VAL},
      {"density", "kg/m^3", monohydra::kPositive, HUGE_VAL}};
  double parameter(uint32_t index) const { return values_[index]; }
  void set_parameter(uint32_t index, double value) {
    values_[index] = value;
    c_vt_ = values_[1] * values_[0] * std::sqrt(2.0 / values_[2]);  // Eq. 25
  }

  mh_status setup() {
    const mh_host* h = host_;
    double area = 0.0, cd = 0.0, rho = 0.0, p_tr = 0.0;
    if (positive_option(h, "area", 1, 0.0, "a positive orifice area (m^2)", &area) != MH_OK ||
        positive_option(h, "discharge_coefficient", 1, 0.0, "a positive discharge coefficient",
                        &cd) != MH_OK ||
        positive_option(h, "density", 1, 0.0, "a positive fluid density (kg/m^3)", &rho) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    c_vt_ = cd * area * std::sqrt(2.0 / rho);  // Eq. 25
    values_ = {area, cd, rho};
    law_ = OrificeFlow(p_tr);
    if (add_hydraulic_port(h, "a", MH_PORT_FLOW, kNaN, kNaN, &a_) != MH_OK) return MH_ERROR;
    states_.add(a_);
    if (add_hydraulic_port(h, "b", MH_PORT_FLOW, kNaN, kNaN, &b_) != MH_OK) return MH_ERROR;
    states_.add(b_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK) return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double q = c_vt_ * law_.g(eval.y[a_] - eval.y[b_]);  // Eq. 24
    eval.residual[a_] += q;
    eval.residual[b_] -= q;
    eval.outputs[q_out_] = q;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double*) const {
    const double dq = c_vt_ * law_.slope(eval.y[a_] - eval.y[b_]);  // dQ/dp_a = -dQ/dp_b
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(a_, a_, dq);
    dy.add(a_, b_, -dq);
    dy.add(b_, a_, -dq);
    dy.add(b_, b_, dq);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double c_vt_ = 0.0;               // m^3/(s sqrt(Pa))
  std::array<double, 3> values_{};  // area, discharge_coefficient, density
  OrificeFlow law_;
  int32_t a_ = -1, b_ = -1, q_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Throttle::kDescriptor{
    sizeof(mh_component_descriptor),
    "throttle",
    "Throttle valve (fixed orifice)",
    "monohydra",
    "1.0.0",
    "Flow Q = C_d A sqrt(2/rho) sgn(dp) sqrt|dp| from port a to port b (Eqs. 24-25), laminar "
    "below transition_pressure. Options: area (m^2), discharge_coefficient, density (kg/m^3), "
    "transition_pressure (Pa, default 2e5). Output q (m^3/s)."};

}  // namespace

const monohydra::SubsystemComponent kThrottle = monohydra::subsystem_component<Throttle>();

}  // namespace hyd
