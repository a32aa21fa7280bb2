// sum: y = k_a a + k_b b + k_c c + k_d d, an algebraic state; with k_b = -1
// it is a comparator (a setpoint minus a measurement).
#include "components.hpp"
#include "example_models.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class Sum {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBlocksExample;  // example_models.hpp

  explicit Sum(const mh_host* host) : host_(host) {}

  mh_status setup() {
    static constexpr const char* kInputs[kTerms] = {"a", "b", "c", "d"};
    static constexpr const char* kGains[kTerms] = {"k_a", "k_b", "k_c", "k_d"};
    for (int i = 0; i < kTerms; ++i)
      if (inputs_[i].read(host_, kInputs[i], i < 2 ? 1 : 0, 0.0, states_) != MH_OK ||
          finite_option(host_, kGains[i], 0, 1.0, "a finite weight", &k_[i]) != MH_OK)
        return MH_ERROR;
    const char* unit = "";
    double tolerance = 0.0;
    if (signal_unit_and_tolerance(host_, 1e-9, &unit, &tolerance) != MH_OK) return MH_ERROR;
    return add_signal_state(host_, "y", unit, 0.0, tolerance, &y_, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    double sum = 0.0;
    for (int i = 0; i < kTerms; ++i) sum += k_[i] * inputs_[i].value();
    eval.residual[y_] += eval.y[y_] - sum;
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    dy.add(y_, y_, 1.0);
    for (int i = 0; i < kTerms; ++i) inputs_[i].add(dy, y_, -k_[i]);
    return MH_OK;
  }

 private:
  static constexpr int kTerms = 4;
  const mh_host* host_;
  SignalInput inputs_[kTerms];
  double k_[kTerms] = {1.0, 1.0, 1.0, 1.0};
  int32_t y_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Sum::kDescriptor{
    sizeof(mh_component_descriptor),
    "sum",
    "Sum",
    "monohydra",
    "1.0.0",
    "y = k_a a + k_b b + k_c c + k_d d. Options: a, b (signal ports, required), c, d (optional, "
    "default 0), k_a .. k_d (weights, default 1: k_b = -1 for a difference), unit, tolerance "
    "(default 1e-9). State y (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kSum = monohydra::subsystem_component<Sum>();

}  // namespace ctl
