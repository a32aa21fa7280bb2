#include "time_table.hpp"

#include <algorithm>
#include <cmath>

namespace mh {

bool TimeTable::assign(const double* data, uint32_t rows, std::string& error) {
  rows_.clear();
  memo_t_ = std::numeric_limits<double>::quiet_NaN();
  if (data == nullptr || rows == 0) {
    error = "a table of at least one row [t (s), value]";
    return false;
  }
  for (uint32_t i = 0; i < rows; ++i) {
    const Row row{data[2 * i], data[2 * i + 1]};
    if (!std::isfinite(row.t) || !std::isfinite(row.value)) {
      error = "rows [t (s), value] of finite numbers (row " + std::to_string(i + 1) + " is not)";
      return false;
    }
    if (!rows_.empty() && row.t < rows_.back().t) {
      error = "rows sorted by time, t non-decreasing (row " + std::to_string(i + 1) +
              " goes back in time)";
      return false;
    }
    rows_.push_back(row);
  }
  return true;
}

double TimeTable::lookup(double t) const {
  if (rows_.empty()) return 0.0;
  // The first row later than t: every row before it holds a time <= t, so at
  // a repeated time the later row wins (right-continuity).
  const auto after = std::upper_bound(rows_.begin(), rows_.end(), t,
                                      [](double x, const Row& r) { return x < r.t; });
  if (after == rows_.begin()) return rows_.front().value;
  if (after == rows_.end()) return rows_.back().value;
  const Row& r0 = *(after - 1);
  const Row& r1 = *after;  // r0.t <= t < r1.t, so r1.t > r0.t
  return r0.value + (r1.value - r0.value) * (t - r0.t) / (r1.t - r0.t);
}

std::vector<double> TimeTable::jump_times() const {
  std::vector<double> times;
  for (size_t i = 1; i < rows_.size(); ++i)
    if (rows_[i].t == rows_[i - 1].t && (times.empty() || times.back() != rows_[i].t))
      times.push_back(rows_[i].t);
  return times;
}

}  // namespace mh
