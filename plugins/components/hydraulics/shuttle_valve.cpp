// shuttle-valve: the load-sensing network's selector: a ball between two
// inlets A and B connects the one at the higher pressure to the outlet C and
// seals the other, so a chain of them sends the highest load pressure to the
// pump's LS port. The ball's position is a smooth step of the inlets'
// difference over the switching pressure p_sw (a few kPa: it moves at once):
//   s = (1 + tanh((p_A - p_B) / p_sw)) / 2
//   Q_A = K s g(p_A - p_C),  Q_B = K (1 - s) g(p_B - p_C)   (orifice_flow.hpp's g)
//   A's row += Q_A,  B's row += Q_B,  C's row -= Q_A + Q_B
// K = nominal_flow / g(nominal_pressure). Downstream of C a pilot line takes
// no flow, so p_C settles at max(p_A, p_B) (to the sealed side's s, below
// 1e-8 for a difference of 10 p_sw). Source: docs/hydraulics.md.
#include <cmath>
#include <limits>

#include "components.hpp"
#include "dual.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
enum { kA, kB, kC, kInputs };
using D = Dual<kInputs>;

class ShuttleValve {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kLoadSensingExample;

  explicit ShuttleValve(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double q_nom = 0.0, p_nom = 0.0, p_tr = 0.0;
    if (positive_option(h, "nominal_flow", 0, 1e-5,
                        "a positive nominal flow (m^3/s) of the open side", &q_nom) != MH_OK ||
        positive_option(h, "nominal_pressure", 0, 5e5,
                        "a positive pressure drop (Pa) at the nominal flow", &p_nom) != MH_OK ||
        positive_option(h, "switching_pressure", 0, 1e4,
                        "a positive switching pressure (Pa) over which the ball moves",
                        &p_sw_) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    law_ = OrificeFlow(p_tr);
    k_ = q_nom / law_.g(p_nom);
    for (auto [key, index] : {std::pair<const char*, int32_t*>{"A", &a_}, {"B", &b_}, {"C", &c_}}) {
      if (add_hydraulic_port(h, key, MH_PORT_FLOW, kNaN, kNaN, index) != MH_OK) return MH_ERROR;
      states_.add(*index);
    }
    return MH_OK;
  }

  struct Flows {
    D from_a, from_b;
  };
  Flows flows(const mh_subsystem_eval& eval) const {
    const D a = D::input(eval.y[a_], kA), b = D::input(eval.y[b_], kB);
    const D c = D::input(eval.y[c_], kC);
    const double th = std::tanh((a.v - b.v) / p_sw_);
    const D s = chain(a - b, 0.5 * (1.0 + th), 0.5 * (1.0 - th * th) / p_sw_);
    Flows f;
    f.from_a = k_ * (s * orifice(law_, a - c));
    f.from_b = k_ * ((D::constant(1.0) - s) * orifice(law_, b - c));
    return f;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const Flows f = flows(eval);
    eval.residual[a_] += f.from_a.v;
    eval.residual[b_] += f.from_b.v;
    eval.residual[c_] -= f.from_a.v + f.from_b.v;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double*) const {
    const Flows f = flows(eval);
    const int32_t of[kInputs] = {a_, b_, c_};
    monohydra::JacobianBlock dy(states_, d_dy);
    for (int k = 0; k < kInputs; ++k) {
      const size_t i = static_cast<size_t>(k);
      dy.add(a_, of[k], f.from_a.d[i]);
      dy.add(b_, of[k], f.from_b.d[i]);
      dy.add(c_, of[k], -f.from_a.d[i] - f.from_b.d[i]);
    }
    return MH_OK;
  }

  // Nothing stored; each side throttles Q dp >= 0 (g is odd).
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const Flows f = flows(eval);
    stored = 0.0;
    dissipation = f.from_a.v * (eval.y[a_] - eval.y[c_]) + f.from_b.v * (eval.y[b_] - eval.y[c_]);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  OrificeFlow law_;
  double k_ = 0.0, p_sw_ = 1e4;
  int32_t a_ = -1, b_ = -1, c_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor ShuttleValve::kDescriptor{
    sizeof(mh_component_descriptor),
    "shuttle-valve",
    "Shuttle valve",
    "monohydra",
    "1.0.0",
    "Connects the higher-pressure inlet (A or B) to outlet C and seals the other: the "
    "load-sensing network's selector. Options: nominal_flow (m^3/s, default 1e-5) at "
    "nominal_pressure (Pa, default 5e5), switching_pressure (Pa, default 1e4), "
    "transition_pressure (Pa, default 2e5)."};

}  // namespace

const monohydra::SubsystemComponent kShuttleValve = monohydra::subsystem_component<ShuttleValve>();

}  // namespace hyd
