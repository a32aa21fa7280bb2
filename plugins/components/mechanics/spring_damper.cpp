// A linear spring and a linear damper in parallel between two body points:
// tension T = k (l - l0) + c ldot. No states: its only coupling to the Newton
// step is the force it applies to the bodies.
#include "components.hpp"
#include "example_models.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/visual.h"
#include "point_pair.hpp"

namespace mech {
namespace {

class SpringDamper {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kSliderExample;  // example_models.hpp

  explicit SpringDamper(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    if (monohydra::options(h).option_number(h, "stiffness", 1, 0.0, &k_) != MH_OK ||
        monohydra::options(h).option_number(h, "damping", 0, 0.0, &c_) != MH_OK ||
        monohydra::options(h).option_number(h, "free_length", 1, 0.0, &l0_) != MH_OK)
      return MH_ERROR;
    if (k_ < 0.0)
      return monohydra::options(h).option_error(h, "stiffness", "a non-negative stiffness (N/m)");
    if (c_ < 0.0)
      return monohydra::options(h).option_error(h, "damping", "a non-negative damping (N s/m)");
    if (l0_ < 0.0)
      return monohydra::options(h).option_error(h, "free_length", "a non-negative length (m)");
    int32_t a = -1, b = -1;
    if (monohydra::subsystem_setup(h).add_point(h, "a", &a) != MH_OK ||
        monohydra::subsystem_setup(h).add_point(h, "b", &b) != MH_OK)
      return MH_ERROR;
    return declare_link(h, a, b);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    PointPair pp;
    if (!pp.measure(&eval)) {
      host_->log(host_, MH_LOG_ERROR, "the spring-damper's points coincide: no direction");
      return MH_ERROR;
    }
    pp.apply_tension(&eval, k_ * (pp.length - l0_) + c_ * pp.rate);
    return MH_OK;
  }

  // No states, so no jacobian: the host needs none. Its point forces' own
  // derivatives and, with no states, an empty coupling.
  mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
                                 double* dF_dv) const {
    PointPair pp;
    if (!pp.measure(&eval)) return MH_DISCARD;
    pp.tension_jacobian(&eval, k_ * (pp.length - l0_) + c_ * pp.rate, k_, c_, dF_dp, dF_dv);
    return MH_OK;
  }
  mh_status coupling_jacobian(const mh_subsystem_eval&, double*, double*, double*, double*) const {
    return MH_OK;
  }

  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    PointPair pp;
    if (!pp.measure(&eval)) return MH_DISCARD;
    const double stretch = pp.length - l0_;
    stored = 0.5 * k_ * stretch * stretch;
    dissipation = c_ * pp.rate * pp.rate;
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double k_ = 0.0, c_ = 0.0, l0_ = 0.0;
};

const mh_component_descriptor SpringDamper::kDescriptor{
    sizeof(mh_component_descriptor),
    "spring-damper",
    "Linear spring-damper",
    "monohydra",
    "1.0.0",
    "Spring and damper in parallel between points a and b: tension k (l - l0) + c dl/dt. "
    "Options: stiffness (N/m), damping (N s/m, default 0), free_length (m)."};

}  // namespace

const monohydra::SubsystemComponent kSpringDamper = monohydra::subsystem_component<SpringDamper>();

}  // namespace mech
