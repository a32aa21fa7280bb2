// valve-4-3: a 4/3 directional control valve (Eq. 26) whose spool U (V)
// follows the reference U_ref(t) with first-order dynamics (Eq. 27):
//   U's row += tau dU/dt - (U_ref(t) - U)
// Flows, each Q = C_vd |U| g(p_from - p_to) (orifice_flow.hpp), adding +Q to
// the row of the node it leaves and -Q to the row of the node it enters:
//   U >= 0:  P -> A  (Q_PA = Q_d1 of the case study)  and  B -> T (Q_BT = Q_3d)
//   U <  0:  A -> T  (Q_AT = -Q_d1)                     and  P -> B (Q_PB = -Q_3d)
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "orifice_flow.hpp"
#include "time_table.hpp"
#include "touched_states.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class Valve43 {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kValve43Example;  // example_models.hpp

  explicit Valve43(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double p_tr = 0.0, u0 = 0.0, tolerance = 0.0;
    const double* table = nullptr;
    uint32_t rows = 0;
    if (positive_option(h, "flow_coefficient", 1, 0.0,
                        "a positive flow coefficient C_vd (m^3/(s sqrt(Pa) V))", &c_vd_) != MH_OK ||
        positive_option(h, "time_constant", 1, 0.0, "a positive spool time constant tau (s)",
                        &tau_) != MH_OK ||
        monohydra::options(h).option_table(h, "reference", 1, 2, &table, &rows) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_spool", 0, 0.0, &u0) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-7, "a positive spool tolerance (V)", &tolerance) !=
            MH_OK ||
        positive_option(h, "spool_limit", 0, 10.0, "a positive spool limit (V)", &limit_) != MH_OK)
      return MH_ERROR;
    std::string error;
    if (!reference_.assign(table, rows, error))
      return monohydra::options(h).option_error(h, "reference", error.c_str());
    if (!std::isfinite(u0))
      return monohydra::options(h).option_error(h, "initial_spool", "a finite spool position (V)");
    law_ = OrificeFlow(p_tr);
    if (add_hydraulic_port(h, "P", MH_PORT_FLOW, kNaN, kNaN, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    if (add_hydraulic_port(h, "T", MH_PORT_FLOW, kNaN, kNaN, &t_) != MH_OK) return MH_ERROR;
    states_.add(t_);
    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &a_) != MH_OK) return MH_ERROR;
    states_.add(a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &b_) != MH_OK) return MH_ERROR;
    states_.add(b_);
    // The spool is the control signal the reference drives: its range is the
    // reference's, [-U_max, U_max] with U_max = spool_limit (10 V by default).
    mh_state_spec spool = monohydra::state_spec("U", "V", u0, tolerance);
    spool.role = MH_ROLE_CONTROL_SIGNAL;
    spool.range_min = -limit_;
    spool.range_max = limit_;
    if (monohydra::subsystem_setup(h).add_state(h, &spool, &u_) != MH_OK) return MH_ERROR;
    states_.add(u_);
    const mh_output_spec u_ref = monohydra::output_spec("U_ref", "V");
    if (monohydra::outputs(h).add_output(h, &u_ref, &u_ref_out_) != MH_OK) return MH_ERROR;
    // The reference's steps: the host lands a step end on each and restarts the
    // integrator there.
    for (double t : reference_.jump_times())
      if (monohydra::subsystem_setup(h).add_time_event(h, t) != MH_OK) return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double u = eval.y[u_];
    const double u_ref = reference(eval.t);
    eval.residual[u_] += tau_ * eval.ydot[u_] - (u_ref - u);  // Eq. 27
    eval.outputs[u_ref_out_] = u_ref;
    for (const Path& path : paths(u)) {
      const double q = flow(path, eval.y);
      eval.residual[path.from] += q;
      eval.residual[path.to] -= q;
    }
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    JacobianBlock dy(states_, d_dy);
    dy.add(u_, u_, 1.0);
    JacobianBlock(states_, d_dydot).add(u_, u_, tau_);
    const double u = eval.y[u_];
    for (const Path& path : paths(u)) {
      const double dp = eval.y[path.from] - eval.y[path.to];
      const double dq_dp = c_vd_ * std::abs(u) * law_.slope(dp);  // d/dp_from = -d/dp_to
      const double dq_du = c_vd_ * (u >= 0.0 ? 1.0 : -1.0) * law_.g(dp);
      // Row `from` gets +Q, row `to` gets -Q.
      dy.add(path.from, path.from, dq_dp);
      dy.add(path.from, path.to, -dq_dp);
      dy.add(path.from, u_, dq_du);
      dy.add(path.to, path.from, -dq_dp);
      dy.add(path.to, path.to, dq_dp);
      dy.add(path.to, u_, -dq_du);
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
    return c_vd_ * std::abs(y[u_]) * law_.g(y[path.from] - y[path.to]);  // Eq. 26
  }
  double reference(double t) const { return std::clamp(reference_.value(t), -limit_, limit_); }

  const mh_host* host_;
  double c_vd_ = 0.0;    // m^3/(s sqrt(Pa) V)
  double tau_ = 0.0;     // s
  double limit_ = 10.0;  // V
  OrificeFlow law_;
  TimeTable reference_;
  int32_t p_ = -1, t_ = -1, a_ = -1, b_ = -1, u_ = -1, u_ref_out_ = -1;
  TouchedStates states_;
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
    "reference (rows [t (s), U_ref (V)], linear between rows, a repeated time is a step), "
    "transition_pressure (Pa, default 2e5), initial_spool (V, default 0), tolerance (V, default "
    "1e-7), spool_limit (V, default 10). Output U_ref (V). U is a control signal of range "
    "[-spool_limit, spool_limit]."};

}  // namespace

const monohydra::SubsystemComponent kValve43 = monohydra::subsystem_component<Valve43>();

}  // namespace hyd
