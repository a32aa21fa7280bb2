// check-valve: passes flow only from its inlet (port A) to its outlet (port
// B), once the pressure difference exceeds the cracking pressure of its
// spring; closed it does not leak (pressure_valve.hpp has the law).
#include "components.hpp"
#include "example_models.hpp"
#include "pressure_valve.hpp"

namespace hyd {
namespace {

struct CheckTraits {
  static constexpr const char* kExampleModel = kCheckValveExample;
  static constexpr const char* kInlet = "A";
  static constexpr const char* kOutlet = "B";
  static constexpr double kMinCracking = 0.0;  // a check valve without a spring cracks at 0
  static constexpr const char* kCrackingExpected = "a non-negative cracking pressure (Pa)";
};

}  // namespace

template <>
const mh_component_descriptor PressureValve<CheckTraits>::kDescriptor{
    sizeof(mh_component_descriptor),
    "check-valve",
    "Check (non-return) valve",
    "monohydra",
    "1.0.0",
    "Flow only from port A to port B: closed for p_A - p_B <= cracking_pressure, opening over "
    "override_pressure; the open valve passes nominal_flow at nominal_pressure (default "
    "cracking + override). Options: cracking_pressure (Pa), override_pressure (Pa), nominal_flow "
    "(m^3/s), nominal_pressure (Pa), smoothing (default 0.1), transition_pressure (Pa, default "
    "2e5). Output q (m^3/s)."};

const monohydra::SubsystemComponent kCheckValve =
    monohydra::subsystem_component<PressureValve<CheckTraits>>();

}  // namespace hyd
