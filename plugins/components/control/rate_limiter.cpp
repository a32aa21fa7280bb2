// rate-limiter: y follows u at most at the rates `rising` and `falling`:
//   dy/dt = min(max((u - y) / T, -falling), rising)
// T, small, is how closely y tracks u while the rate is not limited (a pure
// limiter is T -> 0, which is not a differential equation the Newton step
// can solve; T of a few steps keeps it smooth enough to converge).
#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class RateLimiter {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit RateLimiter(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const char* unit = "";
    double tolerance = 0.0, y0 = 0.0;
    if (input_.read(host_, "input", 1, 0.0, states_) != MH_OK ||
        positive_option(host_, "rising", 1, 0.0, "a positive rising rate limit (unit/s)",
                        &rising_) != MH_OK ||
        positive_option(host_, "falling", 0, rising_, "a positive falling rate limit (unit/s)",
                        &falling_) != MH_OK ||
        positive_option(host_, "time_constant", 0, 1e-2, "a positive tracking time constant T (s)",
                        &t_) != MH_OK ||
        finite_option(host_, "initial", 0, 0.0, "a finite initial value", &y0) != MH_OK ||
        signal_unit_and_tolerance(host_, 1e-9, &unit, &tolerance) != MH_OK)
      return MH_ERROR;
    return add_signal_state(host_, "y", unit, y0, tolerance, &y_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    double slope = 0.0;
    const double rate = clamp_slope((input_.value() - eval.y[y_]) / t_, -falling_, rising_, &slope);
    eval.residual[y_] += eval.ydot[y_] - rate;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    double slope = 0.0;
    clamp_slope((input_.value() - eval.y[y_]) / t_, -falling_, rising_, &slope);
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(y_, y_, slope / t_);
    input_.add(dy, y_, -slope / t_);
    monohydra::JacobianBlock(states_, d_dydot).add(y_, y_, 1.0);
    return MH_OK;
  }

 private:
  const mh_host* host_;
  SignalInput input_;
  double rising_ = 0.0, falling_ = 0.0, t_ = 1e-2;
  int32_t y_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor RateLimiter::kDescriptor{
    sizeof(mh_component_descriptor),
    "rate-limiter",
    "Rate limiter",
    "monohydra",
    "1.0.0",
    "dy/dt = (input - y) / T clamped to [-falling, rising]. Options: input (a signal port), "
    "rising (unit/s), falling (unit/s, default rising), time_constant T (s, default 0.01), "
    "initial (default 0), unit, tolerance (default 1e-9). State y."};

}  // namespace

const monohydra::SubsystemComponent kRateLimiter = monohydra::subsystem_component<RateLimiter>();

}  // namespace ctl
