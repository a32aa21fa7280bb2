// saturation: y = min(max(u, lower), upper), an algebraic state whose slope is
// 1 between the limits and 0 beyond them.
#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class Saturation {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit Saturation(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const char* unit = "";
    double tolerance = 0.0;
    if (input_.read(host_, "input", 1, 0.0, states_) != MH_OK ||
        limits_option(host_, "lower", "upper", &lower_, &upper_) != MH_OK ||
        signal_unit_and_tolerance(host_, 1e-9, &unit, &tolerance) != MH_OK)
      return MH_ERROR;
    return add_signal_state(host_, "y", unit, 0.0, tolerance, &y_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    double slope = 0.0;
    eval.residual[y_] += eval.y[y_] - clamp_slope(input_.value(), lower_, upper_, &slope);
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    double slope = 0.0;
    clamp_slope(input_.value(), lower_, upper_, &slope);
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(y_, y_, 1.0);
    input_.add(dy, y_, -slope);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  SignalInput input_;
  double lower_ = -kInf, upper_ = kInf;
  int32_t y_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Saturation::kDescriptor{
    sizeof(mh_component_descriptor),
    "saturation",
    "Saturation",
    "monohydra",
    "1.0.0",
    "y = input clamped to [lower, upper]. Options: input (a signal port), lower, upper (default "
    "unbounded, lower < upper), unit, tolerance (default 1e-9). State y (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kSaturation = monohydra::subsystem_component<Saturation>();

}  // namespace ctl
