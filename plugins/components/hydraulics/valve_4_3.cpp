// valve-4-3: a 4/3 directional control valve (Eq. 26) whose spool U (V)
// follows the reference U_ref(t) with first-order dynamics (Eq. 27):
//   U's row += tau dU/dt - (U_ref(t) - U)
// Flows, each Q = C_vd |U| g(p_from - p_to) (orifice_flow.hpp), adding +Q to
// the row of the node it leaves and -Q to the row of the node it enters:
//   U >= 0:  P -> A  (Q_PA = Q_d1 of the case study)  and  B -> T (Q_BT = Q_3d)
//   U <  0:  A -> T  (Q_AT = -Q_d1)                     and  P -> B (Q_PB = -Q_3d)
#include <array>
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "orifice_flow.hpp"
#include "spool.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class Valve43 {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kValve43Example;  // example_models.hpp

  explicit Valve43(const mh_host* host) : host_(host) {}

  // Changed in place (parameters.h).
  static constexpr monohydra::ParameterSpec kParameters[] = {
      {"flow_coefficient", "m^3/(s sqrt(Pa) V)", monohydra::kPositive, HUGE_VAL},
      {"time_constant", "s", monohydra::kPositive, HUGE_VAL}};
  double parameter(uint32_t index) const { return index == 0 ? c_vd_ : spool_.time_constant(); }
  void set_parameter(uint32_t index, double value) {
    if (index == 0)
      c_vd_ = value;
    else
      spool_.set_time_constant(value);
  }

  mh_status setup() {
    const mh_host* h = host_;
    double p_tr = 0.0;
    if (positive_option(h, "flow_coefficient", 1, 0.0,
                        "a positive flow coefficient C_vd (m^3/(s sqrt(Pa) V))", &c_vd_) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    law_ = OrificeFlow(p_tr);
    if (add_hydraulic_port(h, "P", MH_PORT_FLOW, kNaN, kNaN, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    if (add_hydraulic_port(h, "T", MH_PORT_FLOW, kNaN, kNaN, &t_) != MH_OK) return MH_ERROR;
    states_.add(t_);
    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &a_) != MH_OK) return MH_ERROR;
    states_.add(a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &b_) != MH_OK) return MH_ERROR;
    states_.add(b_);
    // The spool U, its reference signal's options and output (spool.hpp).
    return spool_.setup(h, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    spool_.evaluate(eval);  // Eq. 27
    const double u = eval.y[spool_.state()];
    for (const Path& path : paths(u)) {
      const double q = flow(path, eval.y);
      eval.residual[path.from] += q;
      eval.residual[path.to] -= q;
    }
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    spool_.jacobian(states_, d_dy, d_dydot);
    monohydra::JacobianBlock dy(states_, d_dy);
    const int32_t us = spool_.state();
    const double u = eval.y[us];
    for (const Path& path : paths(u)) {
      const double dp = eval.y[path.from] - eval.y[path.to];
      const double dq_dp = c_vd_ * std::abs(u) * law_.slope(dp);  // d/dp_from = -d/dp_to
      const double dq_du = c_vd_ * (u >= 0.0 ? 1.0 : -1.0) * law_.g(dp);
      // Row `from` gets +Q, row `to` gets -Q.
      dy.add(path.from, path.from, dq_dp);
      dy.add(path.from, path.to, -dq_dp);
      dy.add(path.from, us, dq_du);
      dy.add(path.to, path.from, -dq_dp);
      dy.add(path.to, path.to, dq_dp);
      dy.add(path.to, us, -dq_du);
    }
    return MH_OK;
  }

 private:
  struct Path {
    int32_t from, to;  // the flow leaves node `from` and enters node `to`
  };
  using Paths = std::array<Path, 2>;

  // The two open paths for a spool position (Eq. 26 with the valve's crossover).
  Paths paths(double u) const {
    if (u >= 0.0) return {Path{p_, a_}, Path{b_, t_}};
    return {Path{a_, t_}, Path{p_, b_}};
  }
  double flow(const Path& path, const double* y) const {
    return c_vd_ * std::abs(y[spool_.state()]) * law_.g(y[path.from] - y[path.to]);  // Eq. 26
  }

  const mh_host* host_;
  double c_vd_ = 0.0;  // m^3/(s sqrt(Pa) V)
  OrificeFlow law_;
  Spool spool_;
  int32_t p_ = -1, t_ = -1, a_ = -1, b_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Valve43::kDescriptor{
    sizeof(mh_component_descriptor),
    "valve-4-3",
    "4/3 directional control valve",
    "monohydra",
    "1.0.0",
    "Ports P, T, A, B; state U (V), the spool, follows the reference with tau dU/dt = U_ref - U "
    "(Eq. 27); flows C_vd |U| sgn(dp) sqrt|dp| P->A and B->T for U >= 0, A->T and P->B for "
    "U < 0 (Eq. 26). Options: flow_coefficient (m^3/(s sqrt(Pa) V)), time_constant (s), "
    "reference (a signal: rows [t (s), U_ref (V)], linear between rows, a repeated time is a "
    "step, the name of one of the model's inputs, or a state 'instance.state' such as a "
    "controller's output u), "
    "transition_pressure (Pa, default 2e5), initial_spool (V, default 0), tolerance (V, default "
    "1e-7), spool_limit (V, default 10). Output U_ref (V). U is a control signal of range "
    "[-spool_limit, spool_limit]."};

}  // namespace

const monohydra::SubsystemComponent kValve43 = monohydra::subsystem_component<Valve43>();

}  // namespace hyd
