// relief-valve: a direct-acting pressure-relief valve from a protected node
// (port P) to tank (port T). It stays shut below its set (cracking) pressure
// and opens along its pressure-flow gradient (the override) to fully open,
// as catalogues give it (pressure_valve.hpp has the law).
#include "components.hpp"
#include "example_models.hpp"
#include "pressure_valve.hpp"

namespace hyd {
namespace {

struct ReliefTraits {
  static constexpr const char* kExampleModel = kReliefValveExample;
  static constexpr const char* kInlet = "P";
  static constexpr const char* kOutlet = "T";
  static constexpr double kMinCracking = 1e-300;  // > 0: a set pressure
  static constexpr const char* kCrackingExpected = "a positive set (cracking) pressure (Pa)";
};

}  // namespace

template <>
const mh_component_descriptor PressureValve<ReliefTraits>::kDescriptor{
    sizeof(mh_component_descriptor),
    "relief-valve",
    "Pressure-relief valve",
    "monohydra",
    "1.0.0",
    "Relieves port P to port T: closed for p_P - p_T <= cracking_pressure, opening over "
    "override_pressure to fully open; the open valve passes nominal_flow at nominal_pressure "
    "(default cracking + override). Options: cracking_pressure (Pa), override_pressure (Pa), "
    "nominal_flow (m^3/s), nominal_pressure (Pa), smoothing (default 0.1), transition_pressure "
    "(Pa, default 2e5). Output q (m^3/s)."};

const monohydra::SubsystemComponent kReliefValve =
    monohydra::subsystem_component<PressureValve<ReliefTraits>>();

}  // namespace hyd
