// monohydra SDK, optional C++17 helper (header-only): the states an instance
// touches, in the order the host numbers its jacobian blocks (subsystem.h,
// docs/sdk.md): first-call order of add_state / find_state / add_port /
// option_signal_port (a port on a state), without repeats. Two ports joined to one node share one
// state, so an instance looks every global index up here rather than counting calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace monohydra {

class TouchedStates {
 public:
  // Records a global state index the host just returned (no-op if known).
  void add(int32_t global) {
    for (int32_t g : globals_)
      if (g == global) return;
    globals_.push_back(global);
  }
  // Position of `global` in the jacobian blocks (it must have been added).
  size_t local(int32_t global) const {
    for (size_t i = 0; i < globals_.size(); ++i)
      if (globals_[i] == global) return i;
    return globals_.size();
  }
  size_t size() const { return globals_.size(); }

 private:
  std::vector<int32_t> globals_;
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
