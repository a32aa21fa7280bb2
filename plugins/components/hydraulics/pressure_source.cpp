// pressure-source: a pump or a tank held at a constant pressure (p_P, p_T of
// the paper's circuit). The imposed pressure enters as a constraint with a
// Lagrange multiplier q, the flow the source delivers into its node:
//   node row  += -q                 (q enters the node)
//   q's row   += p - pressure       (= 0: the node is held at `pressure`)
// so every other component treats a source node like any other node.
#include <cmath>

#include "components.hpp"
#include "example_models.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/signal_port.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

class PressureSource {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kThrottleExample;  // example_models.hpp

  explicit PressureSource(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double tolerance = 0.0, flow_tolerance = 0.0;
    if (pressure_.read(h, "pressure", 1, 0.0, states_) != MH_OK) return MH_ERROR;
    if (!(std::isfinite(pressure_.value()) && pressure_.value() >= 0.0))
      return monohydra::options(h).option_error(h, "pressure",
                                                "a non-negative pressure (Pa) at t = 0");
    if (positive_option(h, "tolerance", 0, 1e-2, "a positive pressure tolerance (Pa)",
                        &tolerance) != MH_OK ||
        positive_option(h, "flow_tolerance", 0, 1e-10, "a positive flow tolerance (m^3/s)",
                        &flow_tolerance) != MH_OK)
      return MH_ERROR;
    if (add_hydraulic_port(h, "p", MH_PORT_EFFORT, pressure_.value(), tolerance, &p_) != MH_OK)
      return MH_ERROR;
    states_.add(p_);
    const mh_state_spec q = monohydra::state_spec("q", "m^3/s", 0.0, flow_tolerance);
    if (monohydra::subsystem_setup(h).add_state(h, &q, &q_) != MH_OK) return MH_ERROR;
    states_.add(q_);
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[p_] -= eval.y[q_];
    eval.residual[q_] += eval.y[p_] - pressure_.value();  // the signal's, at eval.t
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(p_, q_, -1.0);
    dy.add(q_, p_, 1.0);
    pressure_.add(dy, q_, -1.0);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  monohydra::SignalPort pressure_;  // Pa: a number, a table, an input or a state
  int32_t p_ = -1, q_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor PressureSource::kDescriptor{
    sizeof(mh_component_descriptor),
    "pressure-source",
    "Pressure source (pump or tank)",
    "monohydra",
    "1.0.0",
    "Holds its node (port p) at its pressure; state q (m^3/s) is the flow it delivers "
    "into the node. Options: pressure (Pa: a number, a signal table [t, p], an input's name or "
    "a state 'instance.state'), tolerance (Pa, default 1e-2), flow_tolerance "
    "(m^3/s, default 1e-10)."};

}  // namespace

const monohydra::SubsystemComponent kPressureSource =
    monohydra::subsystem_component<PressureSource>();

}  // namespace hyd
