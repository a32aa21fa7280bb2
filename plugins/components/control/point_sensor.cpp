// point-sensor: a body point's world position (x, y, z) as signal states,
// e.g. a boom tip's height; rows x - p_x = 0 etc., algebraic, with their
// derivatives in the point's motion from coupling_jacobian. No force.
#include "components.hpp"
#include "example_models.hpp"
#include "monohydra/cpp/services.hpp"
#include "signal_block.hpp"

namespace ctl {
namespace {

class PointSensor {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kSensorsExample;  // example_models.hpp

  explicit PointSensor(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double tolerance = 0.0, p0[3] = {0.0, 0.0, 0.0};
    if (monohydra::subsystem_setup(h).add_point(h, "p", &p_) != MH_OK ||
        monohydra::subsystem_setup(h).point_position(h, p_, p0) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-9, "a positive position tolerance (m)", &tolerance) !=
            MH_OK)
      return MH_ERROR;
    static constexpr const char* kNames[3] = {"x", "y", "z"};
    for (int j = 0; j < 3; ++j)
      if (add_signal_state(h, kNames[j], "m", p0[j], tolerance, &xyz_[j], states_) != MH_OK)
        return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    for (int j = 0; j < 3; ++j)
      eval.residual[xyz_[j]] += eval.y[xyz_[j]] - eval.point_p[3 * p_ + j];
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval&, double* d_dy, double*) const {
    monohydra::JacobianBlock dy(states_, d_dy);
    for (int j = 0; j < 3; ++j) dy.add(xyz_[j], xyz_[j], 1.0);
    return MH_OK;
  }

  mh_status point_force_jacobian(const mh_subsystem_eval&, double*, double*) const {
    return MH_OK;  // no force
  }

  mh_status coupling_jacobian(const mh_subsystem_eval&, double* dR_dp, double*, double*,
                              double*) const {
    const size_t n = states_.size();
    for (size_t j = 0; j < 3; ++j)
      dR_dp[(3 * static_cast<size_t>(p_) + j) * n + states_.local(xyz_[j])] -= 1.0;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  int32_t p_ = -1, xyz_[3] = {-1, -1, -1};
  monohydra::TouchedStates states_;
};

const mh_component_descriptor PointSensor::kDescriptor{
    sizeof(mh_component_descriptor),
    "point-sensor",
    "Point position sensor",
    "monohydra",
    "1.0.0",
    "The world position x, y, z (m) of point p. Options: tolerance (m, default 1e-9). States "
    "x, y, z (algebraic)."};

}  // namespace

const monohydra::SubsystemComponent kPointSensor = monohydra::subsystem_component<PointSensor>();

}  // namespace ctl
