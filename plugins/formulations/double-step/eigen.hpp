// The one way the double-step plugin includes Eigen, so every translation unit
// sees the same configuration. That the time step allocates nothing is
// checked from outside, by counting every allocation of the process
// (tests/core/step/time_step_allocation_free_test.cpp): Eigen's own
// EIGEN_RUNTIME_NO_MALLOC switch is one flag for the whole process, which
// two instances stepping in two threads would race on (ThreadSanitizer
// found it, .ci/tsan).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
