// gas-accumulator: a gas-charged hydraulic accumulator on one node (port p),
// an example third-party component built against the installed SDK alone.
//
// A gas volume V, precharged to p0 at V0 (the bladder on its stop), is
// compressed polytropically by the oil when the node's pressure p exceeds p0:
//
//   p V^n = p0 V0^n   =>   V(p) = V0 (p0 / p)^(1/n)   for p > p0, else V = V0
//
// (n = 1 isothermal, n = 1.4 adiabatic nitrogen). The oil taken from the node
// is q = -dV/dt = C_gas(p) dp/dt with C_gas = -dV/dp = V / (n p), plus the
// compressibility of the oil in the accumulator's port, V_oil / B_oil. Like a
// hose volume (plugins/components/hydraulics/volume.cpp) its contribution is a storage
// term on the node's row:
//
//   node row += (V_oil / B_oil + C_gas(p)) dp/dt
//
// Stored energy (the work the oil did on the gas since the precharge state):
//   E = integral_V^V0 p dV = p0 V0^n (V^(1-n) - V0^(1-n)) / (n - 1),  n != 1
//   E = p0 V0 ln(V0 / V),                                              n = 1
// which is exactly integral p q dt along any path. Pressures are absolute (Pa).
// Outputs: V_gas (m^3), q = -dV/dt (m^3/s, oil into the gas side) and E_gas (J),
// so integral p q dt = E_gas can be checked from the results.
#include <cmath>
#include <limits>
#include <string>

#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/cpp/subsystem_component.hpp"

namespace {

class GasAccumulator {
 public:
  static const mh_component_descriptor kDescriptor;
  // The model `monohydra check gas-accumulator.so` checks it on: a
  // node charged from 8 MPa through a throttle, from 2.5 MPa.
  static constexpr const char* kExampleModel = R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: acc, type: gas-accumulator, ports: {p: n}, precharge_pressure: 2e6, gas_volume: 1e-3,
     polytropic_exponent: 1.4, oil_volume: 1e-7, initial_pressure: 2.5e6}
  - {name: source, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: line, type: throttle, ports: {a: s, b: n}, area: 1e-5, discharge_coefficient: 0.8,
     density: 850}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

  explicit GasAccumulator(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double oil_volume = 0.0, fluid = 0.0, tolerance = 0.0;
    double initial = std::numeric_limits<double>::quiet_NaN();
    if (positive(h, "precharge_pressure", 1, 0.0, "a positive absolute pressure (Pa)", &p0_) !=
            MH_OK ||
        positive(h, "gas_volume", 1, 0.0, "a positive gas volume at precharge (m^3)", &v0_) !=
            MH_OK ||
        positive(h, "polytropic_exponent", 0, 1.4, "a polytropic exponent >= 1", &n_) != MH_OK ||
        positive(h, "oil_volume", 0, 1e-6, "a positive oil volume of the port (m^3)",
                 &oil_volume) != MH_OK ||
        positive(h, "fluid_bulk_modulus", 0, 1.5e9, "a positive bulk modulus of the oil (Pa)",
                 &fluid) != MH_OK ||
        positive(h, "tolerance", 0, 1e-2, "a positive pressure tolerance (Pa)", &tolerance) !=
            MH_OK ||
        monohydra::options(h).option_number(h, "initial_pressure", 0, initial, &initial) != MH_OK)
      return MH_ERROR;
    if (n_ < 1.0)
      return monohydra::options(h).option_error(h, "polytropic_exponent",
                                                "a polytropic exponent >= 1");
    oil_capacitance_ = oil_volume / fluid;
    mh_port_spec port{};
    port.struct_size = sizeof(mh_port_spec);
    port.key = "p";
    port.domain = "hydraulic";
    port.unit = "Pa";
    port.role = MH_PORT_FLOW;
    port.initial = initial;
    port.abs_tolerance = tolerance;
    if (monohydra::subsystem_setup(h).add_port(h, &port, &p_) != MH_OK) return MH_ERROR;
    const mh_output_spec outputs[] = {monohydra::output_spec("V_gas", "m^3"),
                                      monohydra::output_spec("q", "m^3/s"),
                                      monohydra::output_spec("E_gas", "J")};
    int32_t* indices[] = {&v_out_, &q_out_, &e_out_};
    for (int i = 0; i < 3; ++i)
      if (monohydra::outputs(h).add_output(h, &outputs[i], indices[i]) != MH_OK) return MH_ERROR;
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const double p = eval.y[p_];
    const double q_gas = gas_capacitance(p) * eval.ydot[p_];        // -dV/dt: into the gas side
    eval.residual[p_] += oil_capacitance_ * eval.ydot[p_] + q_gas;  // leaves the node
    put(eval, v_out_, gas_volume(p));
    put(eval, q_out_, q_gas);
    put(eval, e_out_, stored_energy(p));
    return MH_OK;
  }

  // One touched state (the node's pressure): d(row)/dp and d(row)/d(dp/dt).
  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    const double p = eval.y[p_];
    d_dydot[0] += oil_capacitance_ + gas_capacitance(p);
    // d C_gas / dp = d(V / (n p))/dp = -(1 + 1/n) V / (n p^2) above the precharge.
    if (p > p0_) d_dy[0] += -(1.0 + 1.0 / n_) * gas_volume(p) / (n_ * p * p) * eval.ydot[p_];
    return MH_OK;
  }

  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    stored = stored_energy(eval.y[p_]);
    dissipation = 0.0;  // the polytropic gas spring is reversible
    return MH_OK;
  }

 private:
  const mh_host* host_;
  double p0_ = 0.0;               // precharge pressure (Pa, absolute)
  double v0_ = 0.0;               // gas volume at precharge (m^3)
  double n_ = 1.4;                // polytropic exponent
  double oil_capacitance_ = 0.0;  // V_oil / B_oil (m^3/Pa)
  int32_t p_ = -1;
  int32_t v_out_ = -1, q_out_ = -1, e_out_ = -1;

  static mh_status positive(const mh_host* h, const char* key, int required, double fallback,
                            const char* expected, double* out) {
    if (monohydra::options(h).option_number(h, key, required, fallback, out) != MH_OK)
      return MH_ERROR;
    if (!(std::isfinite(*out) && *out > 0.0))
      return monohydra::options(h).option_error(h, key, expected);
    return MH_OK;
  }
  static void put(const mh_subsystem_eval& eval, int32_t index, double value) {
    if (index >= 0 && static_cast<uint32_t>(index) < eval.num_outputs) eval.outputs[index] = value;
  }

  // V(p) = V0 (p0/p)^(1/n) above the precharge, V0 (on the stop) below it.
  double gas_volume(double p) const { return p > p0_ ? v0_ * std::pow(p0_ / p, 1.0 / n_) : v0_; }
  // C_gas = -dV/dp (m^3/Pa): zero on the stop.
  double gas_capacitance(double p) const { return p > p0_ ? gas_volume(p) / (n_ * p) : 0.0; }
  double stored_energy(double p) const {
    const double v = gas_volume(p);
    if (n_ == 1.0) return p0_ * v0_ * std::log(v0_ / v);
    return p0_ * std::pow(v0_, n_) * (std::pow(v, 1.0 - n_) - std::pow(v0_, 1.0 - n_)) / (n_ - 1.0);
  }
};

const mh_component_descriptor GasAccumulator::kDescriptor{
    sizeof(mh_component_descriptor),
    "gas-accumulator",
    "Gas-charged hydraulic accumulator (example plugin)",
    "monohydra examples",
    "1.0.0",
    "A polytropic gas spring p V^n = p0 V0^n on one node (port p), on its stop below the "
    "precharge: node row += (V_oil/B_oil + V/(n p)) dp/dt. Options: precharge_pressure (Pa, "
    "absolute), gas_volume (m^3, at precharge), polytropic_exponent (default 1.4), oil_volume "
    "(m^3, default 1e-6), fluid_bulk_modulus (Pa, default 1.5e9), initial_pressure (Pa, "
    "optional), tolerance (Pa, default 1e-2). Outputs: V_gas, q, E_gas. Energy: the gas's."};

}  // namespace

MONOHYDRA_SUBSYSTEM_PLUGIN(monohydra::subsystem_component<GasAccumulator>());
