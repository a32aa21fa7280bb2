// volume: a lumped hose volume V on one node (Eqs. 22-23). Its storage term
//   node row += V (1/B_oil + 1/B_h) dp/dt
// is the capacitance V_s / B_oil + V_s / B_s of one sub-volume: summed with the
// other sub-volumes on the node (e.g. a cylinder chamber) it is exactly
// V_k / B_ek of Eq. 23, and the node row then reads Eq. 22 multiplied by
// V_k / B_ek: sum(C) dp/dt + sum(outflows) = 0.
// Optional (off by default): a minimum-pressure limit, gas_release.hpp.
#include <array>
#include <cmath>
#include <limits>

#include "components.hpp"
#include "example_models.hpp"
#include "gas_release.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"

namespace hyd {
namespace {

class Volume {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kThrottleExample;  // example_models.hpp

  explicit Volume(const mh_host* host) : host_(host) {}

  // Changed in place (parameters.h): the capacitance follows.
  static constexpr monohydra::ParameterSpec kParameters[] = {
      {"volume", "m^3", monohydra::kPositive, HUGE_VAL},
      {"bulk_modulus", "Pa", monohydra::kPositive, HUGE_VAL},
      {"fluid_bulk_modulus", "Pa", monohydra::kPositive, HUGE_VAL}};
  double parameter(uint32_t index) const { return values_[index]; }
  void set_parameter(uint32_t index, double value) {
    values_[index] = value;
    capacitance_ = values_[0] * (1.0 / values_[2] + 1.0 / values_[1]);
  }

  mh_status setup() {
    const mh_host* h = host_;
    double volume = 0.0, wall = 0.0, fluid = 0.0, tolerance = 0.0;
    double initial = std::numeric_limits<double>::quiet_NaN();
    if (positive_option(h, "volume", 1, 0.0, "a positive volume (m^3)", &volume) != MH_OK ||
        positive_option(h, "bulk_modulus", 1, 0.0, "a positive bulk modulus of the hose wall (Pa)",
                        &wall) != MH_OK ||
        positive_option(h, "fluid_bulk_modulus", 1, 0.0,
                        "a positive bulk modulus of the fluid (Pa)", &fluid) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-2, "a positive pressure tolerance (Pa)",
                        &tolerance) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_pressure", 0, initial, &initial) != MH_OK)
      return MH_ERROR;
    if (gas_.read(h) != MH_OK) return MH_ERROR;
    gas_ = gas_.for_volume(volume);
    capacitance_ = volume * (1.0 / fluid + 1.0 / wall);
    values_ = {volume, wall, fluid};
    if (add_hydraulic_port(h, "p", MH_PORT_FLOW, initial, tolerance, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    eval.residual[p_] += capacitance_ * eval.ydot[p_];
    if (gas_.on()) eval.residual[p_] += gas_.capacitance(eval.y[p_]) * eval.ydot[p_];
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    monohydra::JacobianBlock(states_, d_dydot).add(p_, p_, capacitance_);
    if (gas_.on()) {
      monohydra::JacobianBlock(states_, d_dydot).add(p_, p_, gas_.capacitance(eval.y[p_]));
      monohydra::JacobianBlock(states_, d_dy)
          .add(p_, p_, gas_.capacitance_slope(eval.y[p_]) * eval.ydot[p_]);
    }
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double capacitance_ = 0.0;        // V (1/B_oil + 1/B_h), m^3/Pa
  std::array<double, 3> values_{};  // volume, bulk_modulus, fluid_bulk_modulus
  GasRelease gas_;                  // off unless minimum_pressure is given
  int32_t p_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Volume::kDescriptor{
    sizeof(mh_component_descriptor),
    "volume",
    "Lumped hose volume",
    "monohydra",
    "1.0.0",
    "Stores fluid on its node (port p): V (1/B_oil + 1/B_h) dp/dt (Eqs. 22-23). Options: volume "
    "(m^3), bulk_modulus (Pa, of the hose wall), fluid_bulk_modulus (Pa), initial_pressure (Pa, "
    "optional), tolerance (Pa, default 1e-2); cavitation limit (off by default): "
    "minimum_pressure (Pa), gas_fraction (default 1e-3), gas_reference_pressure (Pa, default "
    "1e5)."};

}  // namespace

const monohydra::SubsystemComponent kVolume = monohydra::subsystem_component<Volume>();

}  // namespace hyd
