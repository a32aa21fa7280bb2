#include "flow_map.hpp"

#include <cmath>

namespace hyd {

bool FlowMap::assign(const double* data, uint32_t rows, const OrificeFlow& law,
                     std::string& error) {
  law_ = law;
  u_.clear();
  d_.clear();
  k_.clear();
  const auto row_text = [](uint32_t i) { return " (row " + std::to_string(i + 1) + ")"; };
  if (data == nullptr || rows == 0) {
    error = "a table of rows [spool (V), pressure drop (Pa), flow (m^3/s)]";
    return false;
  }
  // The pressure drops of the first spool position fix the grid's columns.
  for (uint32_t i = 0; i < rows; ++i) {
    const double u = data[3 * i], dp = data[3 * i + 1], q = data[3 * i + 2];
    if (!std::isfinite(u) || !std::isfinite(dp) || !std::isfinite(q) || u < 0.0 || !(dp > 0.0) ||
        q < 0.0) {
      error = "rows [spool >= 0 (V), pressure drop > 0 (Pa), flow >= 0 (m^3/s)]" + row_text(i);
      return false;
    }
    if (i > 0 && u == data[0]) {
      if (!(dp > d_.back())) {
        error = "the pressure drops of one spool position increasing" + row_text(i);
        return false;
      }
    }
    if (u == data[0]) d_.push_back(dp);
  }
  const size_t n = d_.size();
  if (rows % n != 0) {
    error = "a full grid: every spool position with the " + std::to_string(n) +
            " pressure drops of the first (" + std::to_string(rows) + " rows)";
    return false;
  }
  for (uint32_t i = 0; i < rows; ++i) {
    const size_t column = i % n;
    const double u = data[3 * i], dp = data[3 * i + 1], q = data[3 * i + 2];
    if (column == 0) {
      if (!u_.empty() && !(u > u_.back())) {
        error = "spool positions increasing from one block of rows to the next" + row_text(i);
        return false;
      }
      u_.push_back(u);
    } else if (u != u_.back()) {
      error = "a full grid: every spool position with the " + std::to_string(n) +
              " pressure drops of the first" + row_text(i);
      return false;
    }
    if (dp != d_[column]) {
      error = "a full grid: pressure drop " + std::to_string(d_[column]) +
              " Pa here, as for the "
              "first spool position" +
              row_text(i);
      return false;
    }
    if (u == 0.0 && q != 0.0) {
      error = "zero flow at spool 0 (a closed-centre valve)" + row_text(i);
      return false;
    }
    k_.push_back(q / law_.g(dp));
  }
  first_ = 0;
  if (u_.front() > 0.0) {  // the closed centre: K = 0 at u = 0
    u_.insert(u_.begin(), 0.0);
    k_.insert(k_.begin(), n, 0.0);
    first_ = 1;
  }
  if (u_.size() < 2) {
    error = "at least one spool position above 0";
    return false;
  }
  return true;
}

double FlowMap::flow_of_row(uint32_t row) const {
  const size_t n = d_.size();
  return k_[first_ * n + row] * law_.g(d_[row % n]);
}

void FlowMap::set_flow_of_row(uint32_t row, double q) {
  const size_t n = d_.size();
  k_[first_ * n + row] = q / law_.g(d_[row % n]);
}

void FlowMap::locate(const std::vector<double>& axis, double x, size_t& i, double& w,
                     double& slope) {
  slope = 0.0;
  // At the first grid point itself the slope is the first cell's (the
  // one-sided derivative a spool at |U| = 0 opens along), not the clamp's 0.
  if (axis.size() == 1 || x < axis.front()) {
    i = 0;
    w = 0.0;
    return;
  }
  if (x >= axis.back()) {
    i = axis.size() - 2;
    w = 1.0;
    return;
  }
  i = 0;
  while (x >= axis[i + 1]) ++i;  // tables are short: a scan, no allocation
  const double width = axis[i + 1] - axis[i];
  w = (x - axis[i]) / width;
  slope = 1.0 / width;
}

double FlowMap::flow(double u, double dp, double* dq_du, double* dq_ddp) const {
  const size_t n = d_.size();
  size_t i = 0, j = 0;
  double wu = 0.0, su = 0.0, wd = 0.0, sd = 0.0;
  locate(u_, u, i, wu, su);
  const double adp = std::abs(dp);
  locate(d_, adp, j, wd, sd);
  const size_t j1 = n > 1 ? j + 1 : j;
  const double k00 = k_[i * n + j], k01 = k_[i * n + j1];
  const double k10 = k_[(i + 1) * n + j], k11 = k_[(i + 1) * n + j1];
  const double k0 = k00 + (k01 - k00) * wd, k1 = k10 + (k11 - k10) * wd;  // along dp
  const double k = k0 + (k1 - k0) * wu;                                   // along u
  const double g = law_.g(dp);
  if (dq_du != nullptr) *dq_du = (k1 - k0) * su * g;
  if (dq_ddp != nullptr) {
    const double dk_dadp = ((k01 - k00) + ((k11 - k10) - (k01 - k00)) * wu) * sd;
    *dq_ddp = dk_dadp * (dp >= 0.0 ? 1.0 : -1.0) * g + k * law_.slope(dp);
  }
  return k * g;
}

}  // namespace hyd
