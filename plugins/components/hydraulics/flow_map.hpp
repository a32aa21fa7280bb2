// A metering edge's measured characteristic, as valve catalogues give it: a
// grid of flows Q_ij at spool positions u_i and pressure drops d_j
// (valve_table.cpp). It is stored as the flow coefficient
//   K_ij = Q_ij / g(d_j)        (g the orifice law of orifice_flow.hpp)
// and K is interpolated bilinearly in (u, dp), held constant outside the
// measured pressure drops: Q(u, dp) = K(u, |dp|) g(dp). So the table's points
// come back exactly, Q grows as sqrt(dp) beyond the last measured drop (and
// turns laminar below p_tr like the orifice valve), and a table made from the
// orifice formula Q = C_vd u g(dp) gives that formula back everywhere.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "orifice_flow.hpp"

namespace hyd {

class FlowMap {
 public:
  // Reads `rows` rows [u (V), dp (Pa), Q (m^3/s)] (row-major): a full grid,
  // sorted by u and, within one u, by dp; u >= 0 (a u = 0 column, if given,
  // must have Q = 0: a closed-centre valve), dp > 0, Q >= 0. Without a u = 0
  // column, one of zero flow is added. On a bad table returns false and
  // `error` says what was expected.
  bool assign(const double* data, uint32_t rows, const OrificeFlow& law, std::string& error);

  // Q (m^3/s) at spool opening u >= 0 and drop dp, with dQ/du and dQ/d(dp).
  double flow(double u, double dp, double* dq_du, double* dq_ddp) const;

  double max_opening() const { return u_.back(); }

  // The table's row `row` (as assign read it): its spool opening and flow;
  // a new flow for it, as if the table had given it (its K follows).
  double opening_of_row(uint32_t row) const { return u_[row / d_.size() + first_]; }
  double flow_of_row(uint32_t row) const;
  void set_flow_of_row(uint32_t row, double q);

 private:
  // The cell of x in axis (index i with axis[i] <= x < axis[i+1], clamped) and
  // its weight; `slope` is d(weight)/dx (0 where x is clamped).
  static void locate(const std::vector<double>& axis, double x, size_t& i, double& w,
                     double& slope);

  OrificeFlow law_;
  std::vector<double> u_, d_;  // the grid's spool openings and pressure drops
  std::vector<double> k_;      // K at (u_i, d_j), row-major [i * d_.size() + j]
  size_t first_ = 0;           // the grid's row of the table's first (1: a closed centre added)
};

}  // namespace hyd
