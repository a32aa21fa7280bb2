// first-order-lag: T dy/dt + y = k u, the transfer function k / (1 + T s);
// its row T ydot + y - k u = 0 (a state with a rate: the integrator's).
#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class FirstOrderLag {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit FirstOrderLag(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const char* unit = "";
    double tolerance = 0.0, y0 = 0.0;
    if (input_.read(host_, "input", 1, 0.0, states_) != MH_OK ||
        positive_option(host_, "time_constant", 1, 0.0, "a positive time constant T (s)", &t_) !=
            MH_OK ||
        finite_option(host_, "gain", 0, 1.0, "a finite gain k", &k_) != MH_OK ||
        finite_option(host_, "initial", 0, 0.0, "a finite initial value", &y0) != MH_OK ||
        signal_unit_and_tolerance(host_, 1e-9, &unit, &tolerance) != MH_OK)
      return MH_ERROR;
    return add_signal_state(host_, "y", unit, y0, tolerance, &y_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[y_] += t_ * eval.ydot[y_] + eval.y[y_] - k_ * input_.value();
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double* d_dydot) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(y_, y_, 1.0);
    input_.add(dy, y_, -k_);
    monohydra::JacobianBlock(states_, d_dydot).add(y_, y_, t_);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  SignalInput input_;
  double t_ = 0.0, k_ = 1.0;
  int32_t y_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor FirstOrderLag::kDescriptor{
    sizeof(mh_component_descriptor),
    "first-order-lag",
    "First-order lag",
    "monohydra",
    "1.0.0",
    "T dy/dt + y = gain * input (k / (1 + T s)). Options: input (a signal port), time_constant "
    "T (s), gain (default 1), initial (default 0), unit, tolerance (default 1e-9). State y."};

}  // namespace

const monohydra::SubsystemComponent kFirstOrderLag =
    monohydra::subsystem_component<FirstOrderLag>();

}  // namespace ctl
