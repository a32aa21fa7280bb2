// The conformance checks' three estimates of a function's derivative, one
// column per argument: shared by the tangent's, the formulation's and a
// subsystem's blocks (simulation.cpp, subsystem_blocks.cpp).
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "monohydra/core/simulation.hpp"

namespace mh {

// d rows / d v for the first `n` entries of `v`: forward and backward at
// 1e-6 and central at 1e-5 of the entry's scale (|v|, at least 1e-2 and at
// least `least[c]` when given: a rate's, whose value may be 0): their
// mean is the central difference, a kink (a spool crossing zero) makes the
// analytic entry one of them, and the coarse one's distance estimates the
// differences' own error. Central at 1e-4 and 1e-3 as well: where a row's
// other terms are 1e5 times an entry's, rounding at 1e-6 hides a 1 % error
// of it that a wider step shows (their own distance says whether the row
// is smooth enough there for them). `rows()` evaluates at the current `v`;
// each entry is restored after.
template <class Rows>
void difference_columns(Eigen::VectorXd& v, Eigen::Index n, const Eigen::VectorXd& r0, Rows&& rows,
                        Simulation::TangentSample& out, const Eigen::VectorXd* least = nullptr) {
  const Eigen::Index m = r0.size();
  out.forward.resize(m, n);
  out.backward.resize(m, n);
  out.central_coarse.resize(m, n);
  out.central_wide.resize(m, n);
  out.central_wider.resize(m, n);
  out.column_scale.resize(n);
  for (Eigen::Index c = 0; c < n; ++c) {
    const double v0 = v[c],
                 scale = std::max({1e-2, std::abs(v0), least != nullptr ? (*least)[c] : 0.0});
    out.column_scale[c] = scale;
    const double fine = 1e-6 * scale, coarse = 1e-5 * scale;
    v[c] = v0 + fine;
    out.forward.col(c) = (rows() - r0) / fine;
    v[c] = v0 - fine;
    out.backward.col(c) = (r0 - rows()) / fine;
    v[c] = v0 + coarse;
    out.central_coarse.col(c) = rows();
    v[c] = v0 - coarse;
    out.central_coarse.col(c) = (out.central_coarse.col(c) - rows()) / (2.0 * coarse);
    for (const double wide : {1e-4 * scale, 1e-3 * scale}) {
      Eigen::MatrixXd& to = wide < 5e-4 * scale ? out.central_wide : out.central_wider;
      try {
        v[c] = v0 + wide;
        to.col(c) = rows();
        v[c] = v0 - wide;
        to.col(c) = (to.col(c) - rows()) / (2.0 * wide);
      } catch (const SimulationError&) {
        // Outside what the model takes there (a piston at its stop): the
        // fine pair alone judges this column.
        to.col(c).setConstant(std::numeric_limits<double>::quiet_NaN());
      }
    }
    v[c] = v0;
  }
}

}  // namespace mh
