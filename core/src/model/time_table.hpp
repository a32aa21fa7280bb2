// A piecewise-linear signal of time from a table of rows [t (s), value]: a
// signal option of a component (a valve's reference voltage U_ref(t), Eqs.
// 46-47) or an input's table, evaluated by the host (signals.hpp).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace mh {

class TimeTable {
 public:
  struct Row {
    double t;
    double value;
  };

  // Reads `rows` rows of 2 numbers (row-major [t0, v0, t1, v1, ...]). The times
  // must be finite and non-decreasing; a time given twice is a jump. On a bad
  // table returns false and `error` says what was expected.
  bool assign(const double* data, uint32_t rows, std::string& error);

  // The value at t: the first value before the first row, the last after the
  // last row, linear between rows. At a jump (rows i and i+1 at the same time)
  // the later row holds from that time on (right-continuous).
  // The last time asked and its value are kept: a step evaluates its
  // components many times at one time (Newton's iterations, differences),
  // and the same t gives the same value without the search.
  double value(double t) const {
    if (t == memo_t_) return memo_value_;
    memo_value_ = lookup(t);
    memo_t_ = t;
    return memo_value_;
  }

  // The times at which the signal jumps (each time that appears more than
  // once), ascending, without repeats.
  std::vector<double> jump_times() const;

  const std::vector<Row>& rows() const { return rows_; }

 private:
  double lookup(double t) const;
  std::vector<Row> rows_;
  mutable double memo_t_ = std::numeric_limits<double>::quiet_NaN();  // NaN: nothing kept
  mutable double memo_value_ = 0.0;
};

}  // namespace mh
