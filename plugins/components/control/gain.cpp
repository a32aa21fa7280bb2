// gain: y = k u, an algebraic state (its row y - k u = 0).
#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class Gain {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit Gain(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const char* unit = "";
    double tolerance = 0.0;
    if (input_.read(host_, "input", 1, 0.0, states_) != MH_OK ||
        finite_option(host_, "gain", 1, 0.0, "a finite gain k", &k_) != MH_OK ||
        signal_unit_and_tolerance(host_, 1e-9, &unit, &tolerance) != MH_OK)
      return MH_ERROR;
    return add_signal_state(host_, "y", unit, 0.0, tolerance, &y_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[y_] += eval.y[y_] - k_ * input_.value();
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(y_, y_, 1.0);
    input_.add(dy, y_, -k_);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  SignalInput input_;
  double k_ = 0.0;
  int32_t y_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Gain::kDescriptor{
    sizeof(mh_component_descriptor),
    "gain",
    "Gain",
    "monohydra",
    "1.0.0",
    "y = gain * input. Options: input (a signal port: a table [t, value], an input's name or a "
    "state 'instance.state'), gain, unit (of y, default none), tolerance (default 1e-9). "
    "State y (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kGain = monohydra::subsystem_component<Gain>();

}  // namespace ctl
