// The one way the double-step plugin includes Eigen, so every translation unit
// sees the same configuration. In builds with assertions (Debug) Eigen is
// compiled with EIGEN_RUNTIME_NO_MALLOC, and a NoHeapScope turns any heap
// allocation by Eigen inside it into an assertion failure: predict, residual
// and accept run inside one, so the test suite checks on every step that the
// time step allocates nothing (all buffers are sized in setup).
#pragma once

#ifndef NDEBUG
#define EIGEN_RUNTIME_NO_MALLOC
#endif
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

namespace mh::double_step {

class NoHeapScope {
 public:
#ifndef NDEBUG
  NoHeapScope() : previous_(Eigen::internal::is_malloc_allowed()) {
    Eigen::internal::set_is_malloc_allowed(false);
  }
  ~NoHeapScope() {
    Eigen::internal::set_is_malloc_allowed(previous_);
  }
#else
  // User-provided, so Release builds do not flag the scope variables unused.
  NoHeapScope() {}   // NOLINT(modernize-use-equals-default)
  ~NoHeapScope() {}  // NOLINT(modernize-use-equals-default)
#endif
  NoHeapScope(const NoHeapScope&) = delete;
  NoHeapScope& operator=(const NoHeapScope&) = delete;

 private:
#ifndef NDEBUG
  bool previous_;
#endif
};

}  // namespace mh::double_step
