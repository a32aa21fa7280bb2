// monohydra SDK, optional C++17 helper (header-only): the states an instance
// touches, in the order the host numbers its jacobian blocks (subsystem.h,
// docs/sdk.md): first-call order of add_state / find_state / add_port /
// option_signal_port (a port on a state), without repeats. Two ports joined to one node share one
// state, so an instance looks every global index up here rather than counting calls.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace monohydra {

class TouchedStates {
 public:
  // Records a global state index the host just returned (no-op if known).
  void add(int32_t global) {
    const auto at = find(global);
    if (at != sorted_.end() && at->first == global) return;
    sorted_.insert(at, {global, globals_.size()});
    globals_.push_back(global);
  }
  // Position of `global` in the jacobian blocks (it must have been added):
  // a binary search, so that a block of n states (a hose's ladder) is filled
  // in n log n, not n^2.
  size_t local(int32_t global) const {
    if (globals_.size() <= kLinear) {  // a valve's few states: a scan is cheaper
      for (size_t i = 0; i < globals_.size(); ++i)
        if (globals_[i] == global) return i;
      return globals_.size();
    }
    const auto at = find(global);
    return at != sorted_.end() && at->first == global ? at->second : globals_.size();
  }
  size_t size() const { return globals_.size(); }

 private:
  static constexpr size_t kLinear = 16;
  using Entry = std::pair<int32_t, size_t>;  // global index, position
  std::vector<Entry>::const_iterator find(int32_t global) const {
    return std::lower_bound(sorted_.begin(), sorted_.end(), global,
                            [](const Entry& e, int32_t g) { return e.first < g; });
  }
  std::vector<int32_t> globals_;  // in first-call order
  std::vector<Entry> sorted_;     // by global index
};

// A view of an n x n column-major jacobian block in local (touched) numbering,
// addressed by global state indices. Entries accumulate: two ports on one node
// add to the same entry.
class JacobianBlock {
 public:
  JacobianBlock(const TouchedStates& states, double* values)
      : states_(states), values_(values), n_(states.size()) {}
  // d(row's contribution)/d(column state) += value.
  void add(int32_t row, int32_t column, double value) {
    values_[states_.local(column) * n_ + states_.local(row)] += value;
  }

 private:
  const TouchedStates& states_;
  double* values_;
  size_t n_;
};

}  // namespace monohydra
