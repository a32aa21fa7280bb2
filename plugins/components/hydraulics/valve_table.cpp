// valve-table: a 4/3 directional control valve like valve-4-3 (same ports,
// crossover and spool dynamics, Eqs. 26-27) whose metering edges follow a
// measured characteristic instead of the orifice formula: a table of flow
// against spool position and pressure drop (flow_map.hpp), as catalogues
// give it. One table serves all four edges (a symmetric, critical-centre
// valve): with Q(u, dp) from the table,
//   U >= 0:  P -> A: Q(U, p_P - p_A),   B -> T: Q(U, p_B - p_T)
//   U <  0:  A -> T: Q(-U, p_A - p_T),  P -> B: Q(-U, p_P - p_B)
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "components.hpp"
#include "example_models.hpp"
#include "flow_map.hpp"
#include "host_services.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/touched_states.hpp"
#include "orifice_flow.hpp"
#include "spool.hpp"

namespace hyd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class ValveTable {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kValveTableExample;  // example_models.hpp

  explicit ValveTable(const mh_host* host) : host_(host) {}

  // Changed in place (parameters.h): the flow of every row with the spool
  // open, "flow_table/ROW/2" as a path into the model file writes it (ROW
  // from 0), so that a filter or a fit can identify the characteristic
  // curve point by point.
  uint32_t parameter_count() const { return static_cast<uint32_t>(rows_.size()); }
  monohydra::ParameterSpec parameter_spec(uint32_t index) const {
    return {keys_[index].c_str(), "m^3/s", 0.0, HUGE_VAL};
  }
  double parameter(uint32_t index) const { return map_.flow_of_row(rows_[index]); }
  void set_parameter(uint32_t index, double value) { map_.set_flow_of_row(rows_[index], value); }

  mh_status setup() {
    const mh_host* h = host_;
    double p_tr = 0.0;
    const double* table = nullptr;
    uint32_t rows = 0;
    if (monohydra::options(h).option_table(h, "flow_table", 1, 3, &table, &rows) != MH_OK ||
        positive_option(h, "transition_pressure", 0, 2e5,
                        "a positive laminar-turbulent transition pressure (Pa)", &p_tr) != MH_OK)
      return MH_ERROR;
    std::string error;
    if (!map_.assign(table, rows, OrificeFlow(p_tr), error))
      return monohydra::options(h).option_error(h, "flow_table", error.c_str());
    for (uint32_t row = 0; row < rows; ++row)
      if (map_.opening_of_row(row) > 0.0) {
        rows_.push_back(row);
        keys_.push_back("flow_table/" + std::to_string(row) + "/2");
      }
    if (add_hydraulic_port(h, "P", MH_PORT_FLOW, kNaN, kNaN, &p_) != MH_OK) return MH_ERROR;
    states_.add(p_);
    if (add_hydraulic_port(h, "T", MH_PORT_FLOW, kNaN, kNaN, &t_) != MH_OK) return MH_ERROR;
    states_.add(t_);
    if (add_hydraulic_port(h, "A", MH_PORT_FLOW, kNaN, kNaN, &a_) != MH_OK) return MH_ERROR;
    states_.add(a_);
    if (add_hydraulic_port(h, "B", MH_PORT_FLOW, kNaN, kNaN, &b_) != MH_OK) return MH_ERROR;
    states_.add(b_);
    return spool_.setup(h, states_);
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    spool_.evaluate(eval);
    const double u = eval.y[spool_.state()];
    for (const Path& path : paths(u)) {
      const double q =
          map_.flow(std::abs(u), eval.y[path.from] - eval.y[path.to], nullptr, nullptr);
      eval.residual[path.from] += q;
      eval.residual[path.to] -= q;
    }
    return MH_OK;
  }

  mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot) const {
    spool_.jacobian(states_, d_dy, d_dydot);
    monohydra::JacobianBlock dy(states_, d_dy);
    const int32_t us = spool_.state();
    const double u = eval.y[us];
    for (const Path& path : paths(u)) {
      double dq_du = 0.0, dq_dp = 0.0;  // dp = p_from - p_to
      map_.flow(std::abs(u), eval.y[path.from] - eval.y[path.to], &dq_du, &dq_dp);
      dq_du *= u >= 0.0 ? 1.0 : -1.0;  // d|U|/dU
      dy.add(path.from, path.from, dq_dp);
      dy.add(path.from, path.to, -dq_dp);
      dy.add(path.from, us, dq_du);
      dy.add(path.to, path.from, -dq_dp);
      dy.add(path.to, path.to, dq_dp);
      dy.add(path.to, us, -dq_du);
    }
    return MH_OK;
  }

  // Nothing stored; the metering edges dissipate Q dp >= 0 (Q has the sign of dp).
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    const double u = eval.y[spool_.state()];
    stored = 0.0;
    dissipation = 0.0;
    for (const Path& path : paths(u)) {
      const double dp = eval.y[path.from] - eval.y[path.to];
      dissipation += map_.flow(std::abs(u), dp, nullptr, nullptr) * dp;
    }
    return MH_OK;
  }

 private:
  struct Path {
    int32_t from, to;
  };
  std::array<Path, 2> paths(double u) const {
    if (u >= 0.0) return {Path{p_, a_}, Path{b_, t_}};
    return {Path{a_, t_}, Path{p_, b_}};
  }

  const mh_host* host_;
  FlowMap map_;
  std::vector<uint32_t> rows_;     // the table's rows that are parameters
  std::vector<std::string> keys_;  // and their keys
  Spool spool_;
  int32_t p_ = -1, t_ = -1, a_ = -1, b_ = -1;
  monohydra::TouchedStates states_;
};

const mh_component_descriptor ValveTable::kDescriptor{
    sizeof(mh_component_descriptor),
    "valve-table",
    "4/3 directional control valve from a measured flow table",
    "monohydra",
    "1.0.0",
    "Ports P, T, A, B and spool U as valve-4-3 (tau dU/dt = U_ref - U, Eq. 27; P->A, B->T for "
    "U >= 0, A->T, P->B for U < 0); each edge's flow from flow_table, rows [spool (V), pressure "
    "drop (Pa), flow (m^3/s)] on a full grid, bilinear in the flow coefficient Q/sqrt(dp), "
    "sqrt(dp) beyond the measured drops. Options: flow_table, time_constant (s), reference (rows "
    "[t (s), U_ref (V)], an input's name or a state 'instance.state'), transition_pressure (Pa, "
    "default 2e5), initial_spool "
    "(V, default 0), "
    "tolerance (V, default 1e-7), spool_limit (V, default 10). Output U_ref (V). Parameters: "
    "the flow of each table row with the spool open, flow_table/ROW/2 (m^3/s, ROW from 0)."};

}  // namespace

const monohydra::SubsystemComponent kValveTable = monohydra::subsystem_component<ValveTable>();

}  // namespace hyd
