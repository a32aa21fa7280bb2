// open-centre-valve: a 4/3 directional valve of an open-centre (constant
// flow) circuit. In neutral its centre passage joins P to T, so a fixed pump
// circulates to tank at low pressure; as the spool opens, the bypass edge
// closes and the working edges open, so the pump's pressure rises to what
// the load needs and the flow shifts from the bypass to the load:
//   U's row += tau dU/dt - (U_ref(t) - U)                         (spool.hpp, Eq. 27)
//   U >= 0: P -> A, B -> T;  U < 0: A -> T, P -> B  (C_vd |U| g(dp), as valve-4-3, Eq. 26)
//   the meter-in edge through the section's load check: P -> A (or B) only,
//   C_vd |U| max(g(p_P - p_load), 0), so that a load above the pump's
//   pressure does not flow back into the pump line
//   bypass P -> T:  Q_PT = C_b max(0, 1 - |U| / U_c)^2 g(p_P - p_T)
// C_b = nominal_bypass_flow / g(bypass_pressure): the neutral valve passes the
// pump's flow at its stand-by pressure; U_c (closing_spool) is where the
// bypass is shut. The square makes the closing gradual (metering-in starts
// while the bypass still carries most of the flow) and the flow C1 in U.
// Source: docs/hydraulics.md.
#include <algorithm>
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

class OpenCentreValve {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kOpenCentreValveExample;

  explicit OpenCentreValve(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double p_tr = 0.0, q_bypass = 0.0, p_bypass = 0.0;
    if (positive_option(h, "flow_coefficient", 1, 0.0,
                        "a positive flow coefficient C_vd (m^3/(s sqrt(Pa) V))", &c_vd_) != MH_OK ||
        positive_option(h, "nominal_bypass_flow", 1, 0.0,
                        "a positive flow (m^3/s) the neutral centre passes at bypass_pressure",
                        &q_bypass) != MH_OK ||
        positive_option(h, "bypass_pressure", 0, 1e6,
                        "a positive pressure drop (Pa) of the neutral centre at "
                        "nominal_bypass_flow",
                        &p_bypass) != MH_OK ||
        positive_option(h, "closing_spool", 1, 0.0,
                        "a positive spool position (V) at which the centre passage is shut",
                        &u_c_) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    law_ = OrificeFlow(p_tr);
    c_b_ = q_bypass / law_.g(p_bypass);
    for (auto [key, index] :
         {std::pair<const char*, int32_t*>{"P", &p_}, {"T", &t_}, {"A", &a_}, {"B", &b_}}) {
      if (add_hydraulic_port(h, key, MH_PORT_FLOW, kNaN, kNaN, index) != MH_OK) return MH_ERROR;
      states_.add(*index);
    }
    if (spool_.setup(h, states_) != MH_OK) return MH_ERROR;
    if (u_c_ > spool_.limit())
      return monohydra::options(h).option_error(
          h, "closing_spool",
          ("a closing position within the spool's limit " + short_number(spool_.limit()) + " V")
              .c_str());
    const mh_output_spec q = monohydra::output_spec("q_bypass", "m^3/s");
    return monohydra::outputs(h).add_output(h, &q, &q_out_);
  }

  struct Path {
    int32_t from, to;
  };
  // The working paths open at u (Eq. 26 with the valve's crossover); the
  // one from P is the meter-in edge, behind the load check.
  std::array<Path, 2> paths(double u) const {
    if (u >= 0.0) return {Path{p_, a_}, Path{b_, t_}};
    return {Path{a_, t_}, Path{p_, b_}};
  }
  // g(dp) of a working edge; the meter-in edge passes no flow back.
  double edge(const Path& path, double dp) const {
    const double g = law_.g(dp);
    return path.from == p_ ? std::max(g, 0.0) : g;
  }
  // The bypass's opening factor (1 - |u| / U_c)^2 and its derivative in u.
  double bypass(double u, double* slope) const {
    const double r = 1.0 - std::abs(u) / u_c_;
    if (r <= 0.0) {
      *slope = 0.0;
      return 0.0;
    }
    *slope = -2.0 * r / u_c_ * (u >= 0.0 ? 1.0 : -1.0);
    return r * r;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    spool_.evaluate(eval);  // Eq. 27
    const double u = eval.y[spool_.state()];
    for (const Path& path : paths(u)) {
      const double q = c_vd_ * std::abs(u) * edge(path, eval.y[path.from] - eval.y[path.to]);
      eval.residual[path.from] += q;
      eval.residual[path.to] -= q;
    }
    double slope = 0.0;
    const double q_b = c_b_ * bypass(u, &slope) * law_.g(eval.y[p_] - eval.y[t_]);
    eval.residual[p_] += q_b;
    eval.residual[t_] -= q_b;
    eval.outputs[q_out_] = q_b;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    spool_.jacobian(states_, d_dy, d_dydot);
    monohydra::JacobianBlock dy(states_, d_dy);
    const int32_t us = spool_.state();
    const double u = eval.y[us];
    auto add = [&dy, us](int32_t from, int32_t to, double dq_dp, double dq_du) {
      dy.add(from, from, dq_dp);
      dy.add(from, to, -dq_dp);
      dy.add(from, us, dq_du);
      dy.add(to, from, -dq_dp);
      dy.add(to, to, dq_dp);
      dy.add(to, us, -dq_du);
    };
    for (const Path& path : paths(u)) {
      const double dp = eval.y[path.from] - eval.y[path.to];
      const bool checked = path.from == p_ && dp <= 0.0;  // the load check is shut
      add(path.from, path.to, checked ? 0.0 : c_vd_ * std::abs(u) * law_.slope(dp),
          c_vd_ * (u >= 0.0 ? 1.0 : -1.0) * edge(path, dp));
    }
    double slope = 0.0;
    const double open = bypass(u, &slope);
    const double dp = eval.y[p_] - eval.y[t_];
    add(p_, t_, c_b_ * open * law_.slope(dp), c_b_ * slope * law_.g(dp));
    return MH_OK;
  }

  // Nothing stored; every edge throttles.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const double u = eval.y[spool_.state()];
    stored = 0.0;
    dissipation = 0.0;
    for (const Path& path : paths(u)) {
      const double dp = eval.y[path.from] - eval.y[path.to];
      dissipation += c_vd_ * std::abs(u) * edge(path, dp) * dp;
    }
    double slope = 0.0;
    const double dp = eval.y[p_] - eval.y[t_];
    dissipation += c_b_ * bypass(u, &slope) * law_.g(dp) * dp;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double c_vd_ = 0.0, c_b_ = 0.0, u_c_ = 1.0;
  OrificeFlow law_;
  Spool spool_;
  int32_t p_ = -1, t_ = -1, a_ = -1, b_ = -1, q_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor OpenCentreValve::kDescriptor{
    sizeof(mh_component_descriptor),
    "open-centre-valve",
    "4/3 open-centre directional valve",
    "monohydra",
    "1.0.0",
    "As valve-4-3 (ports P, T, A, B; spool U with time_constant, reference, ...; working edges "
    "C_vd |U| g(dp)), and a centre passage P -> T, open in neutral, that closes as the spool "
    "opens: C_b (1 - |U| / closing_spool)^2 g(p_P - p_T), C_b from nominal_bypass_flow at "
    "bypass_pressure (default 1e6 Pa). The meter-in edge has a load check (no flow back into "
    "P). Output q_bypass (m^3/s)."};

}  // namespace

const monohydra::SubsystemComponent kOpenCentreValve =
    monohydra::subsystem_component<OpenCentreValve>();

}  // namespace hyd
