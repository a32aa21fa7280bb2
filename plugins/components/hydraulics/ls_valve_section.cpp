// ls-valve-section: one section of a load-sensing valve bank. A 4/3 spool U
// (spool.hpp, Eq. 27) opens a meter-in edge P -> A (U >= 0) or P -> B
// (U < 0) and a meter-out edge from the other side to T, each of area
// proportional to |U| (C_vd |U| g(dp), as valve-4-3, Eq. 26); a pressure
// compensator sets the drop across the meter-in edge, so that the section's
// flow follows the spool and not the load:
//   pre-compensated (compensation: pre, the default): upstream of the edge,
//     it throttles P to hold dp_edge = dp_c (its spring) while the supply
//     has the margin: dp_edge = smax(smin(p_P - p_load, dp_c), 0);
//   post-compensated (compensation: post, flow sharing): downstream, every
//     section's compensator throttles to the highest load pressure p_X
//     (port X, the LS network's output): dp_edge = smax(p_P - smax(p_X,
//     p_load - 4 w), 0), the same drop in every section, so that a pump
//     short of flow is shared in proportion to the openings (the inner smax:
//     a compensator only takes pressure away, so the edge passes no flow to
//     a load above the supply while the LS line lags below it);
//   Q_in = C_vd |U| g(dp_edge),  Q_out = C_vd |U| g(p_other - p_T)
// (smin, smax: dual.hpp, rounded over `smoothing_pressure`). The section's
// load-sense port LS is joined to its working port as the spool opens and to
// T in neutral, through a pilot orifice:
//   w_A = h(U / u_ls), w_B = h(-U / u_ls), w_T = 1 - w_A - w_B  (h: smoothstep)
//   Q_LS,k = K_ls w_k g(p_k - p_LS),  k's row += Q_LS,k,  LS's row -= their sum
// Where the section's dissipation goes (outputs of role dissipation-part,
// adding up to its energy op's): the meter-in edge Q_in dp_edge, the
// compensator Q_in (p_P - p_load - dp_edge), the meter-out edge
// Q_out (p_other - p_T) and the load-sense orifices.
// Sources: docs/hydraulics.md.
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "components.hpp"
#include "dual.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "spool.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
enum { kP, kT, kA, kB, kLS, kX, kU, kInputs };
using D = Dual<kInputs>;

// 3x^2 - 2x^3 on [0, 1], 0 below, 1 above, and its slope.
D smoothstep(const D& x) {
  const double v = std::fmin(1.0, std::fmax(0.0, x.v));
  return chain(x, v * v * (3.0 - 2.0 * v), (x.v > 0.0 && x.v < 1.0) ? 6.0 * v * (1.0 - v) : 0.0);
}

class LsValveSection {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kLoadSensingExample;

  explicit LsValveSection(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double p_tr = 0.0;
    const char* compensation = "pre";
    if (positive_option(h, "flow_coefficient", 1, 0.0,
                        "a positive flow coefficient C_vd (m^3/(s sqrt(Pa) V))", &c_vd_) != MH_OK ||
        monohydra::options(h).option_string(h, "compensation", 0, "pre", &compensation) != MH_OK ||
        positive_option(h, "compensator_pressure", 0, 1e6,
                        "a positive compensator setting dp_c (Pa): the drop it holds across the "
                        "meter-in edge",
                        &dp_c_) != MH_OK ||
        positive_option(h, "ls_flow_coefficient", 0, 1e-9,
                        "a positive flow coefficient of the load-sense orifice (m^3/(s sqrt(Pa)))",
                        &k_ls_) != MH_OK ||
        positive_option(h, "ls_opening", 0, 0.5,
                        "a positive spool position (V) at which LS is joined to the working port",
                        &u_ls_) != MH_OK ||
        positive_option(h, "smoothing_pressure", 0, 1e4,
                        "a positive smoothing (Pa) of the compensator's limits", &w_p_) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    if (compensation == nullptr || std::strcmp(compensation, "pre") == 0) {
      post_ = false;
    } else if (std::strcmp(compensation, "post") == 0) {
      post_ = true;
    } else {
      return monohydra::options(h).option_error(h, "compensation",
                                                "pre (compensator upstream of the edge, the "
                                                "default) or post (flow sharing)");
    }
    law_ = OrificeFlow(p_tr);
    for (auto [key, index] : {std::pair<const char*, int32_t*>{"P", &p_},
                              {"T", &t_},
                              {"A", &a_},
                              {"B", &b_},
                              {"LS", &ls_}}) {
      if (add_hydraulic_port(h, key, MH_PORT_FLOW, kNaN, kNaN, index) != MH_OK) return MH_ERROR;
      states_.add(*index);
    }
    if (post_) {
      if (add_hydraulic_port(h, "X", MH_PORT_FLOW, kNaN, kNaN, &x_) != MH_OK) return MH_ERROR;
      states_.add(x_);
    }
    if (spool_.setup(h, states_) != MH_OK) return MH_ERROR;
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    const mh_output_spec dp = monohydra::output_spec("dp_edge", "Pa");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &dp, &dp_out_) != MH_OK)
      return MH_ERROR;
    for (auto [name, index] : {std::pair<const char*, int32_t*>{"P_meter_in", &part_out_[0]},
                               {"P_compensator", &part_out_[1]},
                               {"P_meter_out", &part_out_[2]},
                               {"P_load_sense", &part_out_[3]}}) {
      mh_output_spec spec = monohydra::output_spec(name, "W");
      spec.role = MH_ROLE_DISSIPATION_PART;
      if (monohydra::outputs(h).add_output(h, &spec, index) != MH_OK) return MH_ERROR;
    }
    return MH_OK;
  }

  struct Flows {
    bool to_a = true;
    D edge, in, out, ls_a, ls_b, ls_t;
  };
  Flows flows(const mh_subsystem_eval& eval) const {
    const double* y = eval.y;
    const D p = D::input(y[p_], kP), t = D::input(y[t_], kT), a = D::input(y[a_], kA);
    const D b = D::input(y[b_], kB), ls = D::input(y[ls_], kLS);
    const D u = D::input(y[spool_.state()], kU);
    Flows f;
    f.to_a = u.v >= 0.0;
    const D& load = f.to_a ? a : b;
    const D& other = f.to_a ? b : a;
    const D zero = D::constant(0.0);
    if (post_) {
      // Throttled to the higher of p_X and this section's own load: while the
      // LS line lags below the load, the compensator cannot raise the
      // pressure (without it the edge passed flow P -> load uphill, creating
      // energy). The load enters 4 smoothings down, so that where it is p_X
      // (the highest load's section at rest) the rounding moves the drop by
      // 0.06 of a smoothing only and flow sharing holds.
      const D x = D::input(y[x_], kX);
      f.edge = smooth_max(p - smooth_max(x, load - D::constant(4.0 * w_p_), w_p_), zero, w_p_);
    } else {
      f.edge = smooth_max(smooth_min(p - load, D::constant(dp_c_), w_p_), zero, w_p_);
    }
    const D opening = c_vd_ * chain(u, std::abs(u.v), f.to_a ? 1.0 : -1.0);
    f.in = opening * orifice(law_, f.edge);
    f.out = opening * orifice(law_, other - t);
    const D w_a = smoothstep((1.0 / u_ls_) * u), w_b = smoothstep((-1.0 / u_ls_) * u);
    f.ls_a = k_ls_ * (w_a * orifice(law_, a - ls));
    f.ls_b = k_ls_ * (w_b * orifice(law_, b - ls));
    f.ls_t = k_ls_ * ((D::constant(1.0) - w_a - w_b) * orifice(law_, t - ls));
    return f;
  }

  // Each flow with the rows it leaves (+) and enters (-).
  template <class Add>
  void each(const Flows& f, Add add) const {
    const int32_t load = f.to_a ? a_ : b_, other = f.to_a ? b_ : a_;
    add(f.in, p_, load);
    add(f.out, other, t_);
    add(f.ls_a, a_, ls_);
    add(f.ls_b, b_, ls_);
    add(f.ls_t, t_, ls_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    spool_.evaluate(eval);  // Eq. 27
    const Flows f = flows(eval);
    each(f, [&eval](const D& q, int32_t from, int32_t to) {
      eval.residual[from] += q.v;
      eval.residual[to] -= q.v;
    });
    eval.outputs[q_out_] = f.in.v;
    eval.outputs[dp_out_] = f.edge.v;
    const Parts parts = dissipation_parts(eval, f);
    for (size_t i = 0; i < parts.size(); ++i) eval.outputs[part_out_[i]] = parts[i];
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    spool_.jacobian(states_, d_dy, d_dydot);
    const Flows f = flows(eval);
    const int32_t of[kInputs] = {p_, t_, a_, b_, ls_, x_, spool_.state()};
    monohydra::JacobianBlock dy(states_, d_dy);
    each(f, [&](const D& q, int32_t from, int32_t to) {
      for (int k = 0; k < kInputs; ++k) {
        const double dq = q.d[static_cast<size_t>(k)];
        if (dq == 0.0 || of[k] < 0) continue;
        dy.add(from, of[k], dq);
        dy.add(to, of[k], -dq);
      }
    });
    return MH_OK;
  }

  // Nothing stored; every edge throttles: Q dp >= 0 on each (the meter-in's
  // whole drop P -> load is the edge's and the compensator's).
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const Flows f = flows(eval);
    stored = 0.0;
    dissipation = 0.0;
    each(f, [&](const D& q, int32_t from, int32_t to) {
      dissipation += q.v * (eval.y[from] - eval.y[to]);
    });
    return MH_OK;
  }

  // The energy op's dissipation by where it happens (W): meter-in edge,
  // compensator, meter-out edge, load-sense orifices. The edge takes its
  // drop dp_edge but never more than the whole drop P -> load (with post
  // compensation the section of the highest load sees p_X a little below its
  // load, through the load-sense orifice): the compensator has the rest.
  using Parts = std::array<double, 4>;
  Parts dissipation_parts(const mh_subsystem_eval& eval, const Flows& f) const {
    const double* y = eval.y;
    const int32_t load = f.to_a ? a_ : b_, other = f.to_a ? b_ : a_;
    const double q_in = f.in.v, drop = y[p_] - y[load];
    const double edge = q_in * std::fmin(f.edge.v, std::fmax(drop, 0.0));
    return {
        edge, q_in * drop - edge, f.out.v * (y[other] - y[t_]),
        f.ls_a.v * (y[a_] - y[ls_]) + f.ls_b.v * (y[b_] - y[ls_]) + f.ls_t.v * (y[t_] - y[ls_])};
  }

 private:
  const mh_host* host_;
  double c_vd_ = 0.0, dp_c_ = 1e6, k_ls_ = 1e-9, u_ls_ = 0.5, w_p_ = 1e4;
  bool post_ = false;
  OrificeFlow law_;
  Spool spool_;
  int32_t p_ = -1, t_ = -1, a_ = -1, b_ = -1, ls_ = -1, x_ = -1, q_out_ = -1, dp_out_ = -1;
  std::array<int32_t, 4> part_out_{-1, -1, -1, -1};  // the dissipation parts' outputs
  monohydra::TouchedStates states_;
};

const mh_component_descriptor LsValveSection::kDescriptor{
    sizeof(mh_component_descriptor),
    "ls-valve-section",
    "Load-sensing valve section with pressure compensator",
    "monohydra",
    "1.0.0",
    "Ports P, T, A, B, LS (and X, the highest load pressure, when post-compensated); spool U as "
    "valve-4-3 (time_constant, reference, spool_limit, ...). Meter-in P -> A (U >= 0) or P -> B "
    "with C_vd |U| g(dp_edge), the compensator holding dp_edge = compensator_pressure (default "
    "1e6 Pa; compensation: pre) or p_P - p_X (compensation: post, flow sharing); meter-out to T "
    "uncompensated. LS joins the working port as the spool opens (ls_opening, default 0.5 V; "
    "ls_flow_coefficient, default 1e-9), T in neutral. Options also: smoothing_pressure (Pa, "
    "default 1e4), transition_pressure (Pa, default 2e5). Outputs q (m^3/s, meter-in), dp_edge "
    "(Pa), and the dissipated power by where it happens (W, role dissipation-part): "
    "P_meter_in, P_compensator, P_meter_out, P_load_sense."};

}  // namespace

const monohydra::SubsystemComponent kLsValveSection =
    monohydra::subsystem_component<LsValveSection>();

}  // namespace hyd
