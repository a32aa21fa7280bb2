// pressure-sensor: a hydraulic node's pressure as a signal state, through a
// port that takes no flow; its row p - p_node = 0 (algebraic).
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "monohydra/cpp/services.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class PressureSensor {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kSensorsExample;  // example_models.hpp

  explicit PressureSensor(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double tolerance = 0.0;
    mh_port_spec port{};
    port.struct_size = sizeof port;
    port.key = "a";
    port.domain = "hydraulic";
    port.unit = "Pa";
    port.role = MH_PORT_FLOW;
    port.initial = std::numeric_limits<double>::quiet_NaN();
    port.abs_tolerance = std::numeric_limits<double>::quiet_NaN();
    if (monohydra::subsystem_setup(h).add_port(h, &port, &node_) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-3, "a positive pressure tolerance (Pa)",
                        &tolerance) != MH_OK)
      return MH_ERROR;
    states_.add(node_);
    return add_signal_state(h, "p", "Pa", 0.0, tolerance, &p_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[p_] += eval.y[p_] - eval.y[node_];
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(p_, p_, 1.0);
    dy.add(p_, node_, -1.0);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  int32_t node_ = -1, p_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor PressureSensor::kDescriptor{
    sizeof(mh_component_descriptor),
    "pressure-sensor",
    "Pressure sensor",
    "monohydra",
    "1.0.0",
    "p (Pa): the pressure of the node on port a, which takes no flow. Options: tolerance (Pa, "
    "default 1e-3). State p (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kPressureSensor =
    monohydra::subsystem_component<PressureSensor>();

}  // namespace ctl
