// hose: a hydraulic line with its dynamics, between nodes a and b: the
// lumped transmission line (e.g. Watton, Fluid Power Systems, 1989, Ch. 6;
// Hopsan's and the Modelica libraries' lumped pipes) of n flows and n nodes.
// With A = pi d^2 / 4 and l = L / (n - 1/2):
//   I = rho l / A,  R = 128 mu l / (pi d^4),  C = A l (1/B_oil + 1/B_h)
//   flow k:         I_k dq_k/dt + R_k q_k - (p_{k-1} - p_k) = 0   (row / sqrt(I/C))
//   node k:         C_k dp_k/dt + q_{k+1} - q_k = 0               (k = 1 .. n-1)
//   port a's node:  += q_1,   port b's: += C_n dp_b/dt - q_n
// (p_0 = p_a, p_n = p_b), every I_k = I and C_k = C but the ends': the first
// flow has half a segment's inertance and friction, b's node half a
// segment's compliance, so the totals are the line's (rho L / A, A L / B_e)
// and the ends are symmetric. The ladder starts with an inertance at a and
// ends with a compliance on b: a may be held by a pressure source (its
// pressure imposed, its flow found) and b may be closed (only the hose's
// compliance on it); the other way round, a pressure held on a node with a
// compliance, would leave that compliance's rate undetermined. A wave
// travels at c = sqrt(B_e / rho), 1/B_e = 1/B_oil + 1/B_h, the line's
// delay L/c is the ladder's at low frequencies, and its first resonances
// are the continuous line's to about (pi / 4n)^2.
// Energy: the compression of each node, C_k p_k^2 / 2, and the fluid's
// motion in each segment, I_k q_k^2 / 2, are stored; friction dissipates
// R_k q_k^2. Multiplying node k's row by p_k and flow k's by q_k and adding
// them, d/dt(stored) = p_a q_1 - p_b q_b - dissipation: what enters at a,
// less what leaves at b (q_b, b's other components' take), less friction.
// Optional: the volumes' cavitation limit (gas_release.hpp) on every node
// the hose owns (its inner nodes, half a segment's on b), so a line pulled
// below it by a closing valve's wave holds at the limit instead of going
// negative; the free gas's compression energy is not tracked.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "components.hpp"
#include "example_models.hpp"
#include "gas_release.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "monohydra/sparsity.h"

namespace hyd {
namespace {

constexpr double kPi = 3.14159265358979323846;

class Hose {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kHoseExample;  // example_models.hpp

  explicit Hose(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    double length = 0.0, diameter = 0.0, rho = 0.0, mu = 0.0, wall = 0.0, fluid = 0.0;
    double segments = 0.0, tol_p = 0.0, tol_q = 0.0;
    double initial = std::numeric_limits<double>::quiet_NaN();
    if (positive_option(h, "length", 1, 0.0, "a positive length (m)", &length) != MH_OK ||
        positive_option(h, "inner_diameter", 1, 0.0, "a positive inner diameter (m)", &diameter) !=
            MH_OK ||
        positive_option(h, "density", 1, 0.0, "a positive fluid density (kg/m^3)", &rho) != MH_OK ||
        monohydra::nonnegative_option(h, "viscosity", 1, 0.0,
                                      "a dynamic viscosity >= 0 (Pa s; 0: no friction)",
                                      &mu) != MH_OK ||
        positive_option(h, "bulk_modulus", 1, 0.0, "a positive bulk modulus of the hose wall (Pa)",
                        &wall) != MH_OK ||
        positive_option(h, "fluid_bulk_modulus", 1, 0.0,
                        "a positive bulk modulus of the fluid (Pa)", &fluid) != MH_OK ||
        positive_option(h, "segments", 0, 10.0, "a whole number of segments from 1 to 1000",
                        &segments) != MH_OK ||
        positive_option(h, "tolerance", 0, 1e-2, "a positive pressure tolerance (Pa)", &tol_p) !=
            MH_OK ||
        positive_option(h, "flow_tolerance", 0, 1e-10, "a positive flow tolerance (m^3/s)",
                        &tol_q) != MH_OK ||
        monohydra::options(h).option_number(h, "initial_pressure", 0, initial, &initial) != MH_OK ||
        gas_.read(h) != MH_OK)
      return MH_ERROR;
    if (segments != std::floor(segments) || segments > 1000.0)
      return monohydra::options(h).option_error(h, "segments",
                                                "a whole number of segments from 1 to 1000");
    const auto n = static_cast<size_t>(segments);
    const double l = length / (segments - 0.5), area = 0.25 * kPi * diameter * diameter;
    inertance_ = rho * l / area;
    resistance_ = 128.0 * mu * l / (kPi * diameter * diameter * diameter * diameter);
    capacitance_ = area * l * (1.0 / fluid + 1.0 / wall);
    inner_gas_ = gas_.for_volume(area * l);
    end_gas_ = gas_.for_volume(0.5 * area * l);
    // A flow's row in units of flow: divided by the segment's impedance
    // sqrt(I/C), so its rate's coefficient is the segment's travel time
    // sqrt(I C) = l/c, not an inertance 1e20 times a node's compliance (the
    // rates' LU at t = 0 would take C for round-off).
    row_scale_ = std::sqrt(capacitance_ / inertance_);
    // Ports first (the ends' nodes), then the inner pressures and the flows.
    if (add_hydraulic_port(h, "a", MH_PORT_FLOW, initial, tol_p, &pa_) != MH_OK) return MH_ERROR;
    states_.add(pa_);
    if (add_hydraulic_port(h, "b", MH_PORT_FLOW, initial, tol_p, &pb_) != MH_OK) return MH_ERROR;
    states_.add(pb_);
    const double p0 = std::isfinite(initial) ? initial : 0.0;
    pressures_.assign(n + 1, -1);
    pressures_.front() = pa_;
    pressures_.back() = pb_;
    for (size_t k = 1; k < n; ++k) {
      const std::string name = "p" + std::to_string(k);
      const mh_state_spec spec = monohydra::state_spec(name.c_str(), "Pa", p0, tol_p);
      if (monohydra::subsystem_setup(h).add_state(h, &spec, &pressures_[k]) != MH_OK)
        return MH_ERROR;
      states_.add(pressures_[k]);
    }
    flows_.assign(n, -1);
    for (size_t k = 0; k < n; ++k) {
      const std::string name = "q" + std::to_string(k + 1);
      const mh_state_spec spec = monohydra::state_spec(name.c_str(), "m^3/s", 0.0, tol_q);
      if (monohydra::subsystem_setup(h).add_state(h, &spec, &flows_[k]) != MH_OK) return MH_ERROR;
      states_.add(flows_[k]);
    }
    return declare_entries(h);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    const size_t n = flows_.size();
    for (size_t k = 1; k <= n; ++k) {  // storage: on every node but a, half of it on b
      const int32_t p = pressures_[k];
      eval.residual[p] += node_share(k) * capacitance_ * eval.ydot[p];
      if (gas_.on()) eval.residual[p] += gas(k).capacitance(eval.y[p]) * eval.ydot[p];
    }
    for (size_t k = 0; k < n; ++k) {
      const int32_t q = flows_[k], up = pressures_[k], down = pressures_[k + 1];
      const double share = flow_share(k);
      eval.residual[q] +=
          row_scale_ * (share * (inertance_ * eval.ydot[q] + resistance_ * eval.y[q]) -
                        (eval.y[up] - eval.y[down]));
      eval.residual[up] += eval.y[q];    // leaves the upstream node
      eval.residual[down] -= eval.y[q];  // enters the downstream one
    }
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    monohydra::JacobianBlock dy(states_, d_dy), dydot(states_, d_dydot);
    const size_t n = flows_.size();
    for (size_t k = 1; k <= n; ++k) {
      const int32_t p = pressures_[k];
      dydot.add(p, p, node_share(k) * capacitance_);
      if (gas_.on()) {
        dydot.add(p, p, gas(k).capacitance(eval.y[p]));
        dy.add(p, p, gas(k).capacitance_slope(eval.y[p]) * eval.ydot[p]);
      }
    }
    for (size_t k = 0; k < n; ++k) {
      const int32_t q = flows_[k], up = pressures_[k], down = pressures_[k + 1];
      dydot.add(q, q, row_scale_ * flow_share(k) * inertance_);
      dy.add(q, q, row_scale_ * flow_share(k) * resistance_);
      dy.add(q, up, -row_scale_);
      dy.add(q, down, row_scale_);
      dy.add(up, q, 1.0);
      dy.add(down, q, -1.0);
    }
    return MH_OK;
  }

  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    stored = 0.0;
    dissipation = 0.0;
    for (size_t k = 1; k <= flows_.size(); ++k) {
      const double p = eval.y[pressures_[k]];
      stored += 0.5 * node_share(k) * capacitance_ * p * p;
    }
    for (size_t k = 0; k < flows_.size(); ++k) {
      const double q = eval.y[flows_[k]];
      stored += 0.5 * flow_share(k) * inertance_ * q * q;
      dissipation += flow_share(k) * resistance_ * q * q;
    }
    return MH_OK;
  }

 private:
  // The ladder couples each flow to its two nodes only (sparsity.h): 4n
  // entries besides the diagonal, where a dense block of 2n + 1 states
  // would make the tangent's factorization cost n^3 a step.
  mh_status declare_entries(const mh_host* h) const {
    const auto* sparsity =
        static_cast<const mh_sparsity_service*>(h->get_service(h, MH_SERVICE_SPARSITY));
    if (sparsity == nullptr) return MH_OK;  // a host without it: a dense block
    std::vector<int32_t> rows, columns;
    auto entry = [&](int32_t row, int32_t column) {
      rows.push_back(row);
      columns.push_back(column);
    };
    for (size_t k = 0; k < flows_.size(); ++k) {
      const int32_t q = flows_[k], up = pressures_[k], down = pressures_[k + 1];
      entry(q, up);
      entry(q, down);
      entry(up, q);
      entry(down, q);
    }
    return sparsity->declare_entries(h, static_cast<uint32_t>(rows.size()), rows.data(),
                                     columns.data());
  }

  // The ends' half segments: the first flow's, b's node's.
  double flow_share(size_t k) const { return k == 0 ? 0.5 : 1.0; }
  double node_share(size_t k) const { return k == flows_.size() ? 0.5 : 1.0; }
  const GasRelease& gas(size_t k) const { return k == flows_.size() ? end_gas_ : inner_gas_; }

  const mh_host* host_;
  double inertance_ = 0.0, resistance_ = 0.0, capacitance_ = 0.0;  // per segment
  double row_scale_ = 1.0;                // sqrt(C/I): a flow's row in m^3/s
  GasRelease gas_, inner_gas_, end_gas_;  // the options; a node's, b's half node's
  int32_t pa_ = -1, pb_ = -1;
  std::vector<int32_t> pressures_;  // n + 1 nodes: a, the inner ones, b
  std::vector<int32_t> flows_;      // n segments, from a to b
  monohydra::TouchedStates states_;
};

const mh_component_descriptor Hose::kDescriptor{
    sizeof(mh_component_descriptor),
    "hose",
    "Hose with line dynamics (lumped transmission line)",
    "monohydra",
    "1.0.0",
    "Between ports a and b: segments of the line, each with inertance rho l/A, laminar friction "
    "128 mu l/(pi d^4) and compliance A l (1/B_oil + 1/B_h), l = L/(n - 1/2), from half an "
    "inertance at a to half a compliance on b (a may be held by a pressure source, b may be "
    "closed); waves travel at "
    "sqrt(B_e/rho). Options: length (m), inner_diameter (m), "
    "density (kg/m^3), viscosity (Pa s, 0: no friction), bulk_modulus (Pa, of the wall), "
    "fluid_bulk_modulus (Pa), segments (default 10), initial_pressure (Pa, optional), tolerance "
    "(Pa, default 1e-2), flow_tolerance (m^3/s, default 1e-10), minimum_pressure (Pa: the "
    "cavitation limit on the hose's nodes, off without it), gas_fraction (default 1e-3), "
    "gas_reference_pressure (Pa, default 1e5). States p1 .. p(n-1) (Pa), q1 .. qn (m^3/s, from a "
    "to b). Reports its compression and kinetic energy and its friction's dissipation."};

}  // namespace

const monohydra::SubsystemComponent kHose = monohydra::subsystem_component<Hose>();

}  // namespace hyd
