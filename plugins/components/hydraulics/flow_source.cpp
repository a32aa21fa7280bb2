// flow-source: a fixed-displacement pump driven at constant speed, which
// delivers a constant flow Q into its node whatever the node's pressure (a
// machine's main pump; its pressure is whatever the circuit, and the relief
// valve protecting it, makes it):
//   node row += -Q
// and reports its hydraulic power P = p Q (W), p its node's pressure.
// Unlike `pressure-source` it imposes no pressure, so a circuit fed by it
// needs a relief valve or an open path to tank when every valve is closed.
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/signal_port.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class FlowSource {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kReliefValveExample;  // example_models.hpp

  explicit FlowSource(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    if (flow_.read(h, "flow", 1, 0.0, states_) != MH_OK) return MH_ERROR;
    if (!(std::isfinite(flow_.value()) && flow_.value() >= 0.0))
      return monohydra::options(h).option_error(h, "flow",
                                                "a non-negative, finite flow (m^3/s) at t = 0");
    if (add_hydraulic_port(h, "p", MH_PORT_FLOW, kNaN, kNaN, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    const mh_output_spec q = monohydra::output_spec("q", "m^3/s");
    const mh_output_spec power = monohydra::output_spec("P", "W");
    if (monohydra::outputs(h).add_output(h, &q, &q_out_) != MH_OK ||
        monohydra::outputs(h).add_output(h, &power, &power_out_) != MH_OK)
      return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double flow = flow_.value();  // the signal's, at eval.t
    eval.residual[p_] -= flow;
    eval.outputs[q_out_] = flow;
    eval.outputs[power_out_] = eval.y[p_] * flow;
    return MH_OK;
  }

  // The row depends on no state but the flow's when that is a signal port's.
  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    flow_.add(dy, p_, -1.0);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  monohydra::SignalPort flow_;  // m^3/s: a number, a table, an input or a state
  int32_t p_ = -1, q_out_ = -1, power_out_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor FlowSource::kDescriptor{
    sizeof(mh_component_descriptor),
    "flow-source",
    "Flow source (fixed-displacement pump)",
    "monohydra",
    "1.0.0",
    "Delivers its flow into its node (port p) whatever its pressure. Options: flow "
    "(m^3/s, >= 0 at t = 0: a number, a signal table [t, q], an input's name or a state). Outputs "
    "q (m^3/s), the delivered flow, and P (W), its hydraulic power p q."};

}  // namespace

const monohydra::SubsystemComponent kFlowSource = monohydra::subsystem_component<FlowSource>();

}  // namespace hyd
