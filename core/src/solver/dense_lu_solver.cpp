#include "monohydra/core/dense_lu_solver.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace mh {

struct DenseLuSolver::Impl {
  int n = 0;
  std::vector<int> column_start;
  std::vector<int> row_index;
  Eigen::MatrixXd a;                        // the tangent, dense, column-major
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // sized once: compute() reuses its storage
  Eigen::VectorXd rhs, x;
  bool factored = false;
};

DenseLuSolver::DenseLuSolver(const SparsePattern& pattern) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.n = pattern.size();
  s.column_start = pattern.column_start();
  s.row_index = pattern.row_index();
  s.a.setZero(s.n, s.n);
  s.lu = Eigen::PartialPivLU<Eigen::MatrixXd>(s.n);
  s.rhs.setZero(s.n);
  s.x.setZero(s.n);
}

DenseLuSolver::~DenseLuSolver() = default;

bool DenseLuSolver::factor(const double* values) {
  Impl& s = *impl_;
  s.factored = false;
  for (int c = 0; c < s.n; ++c)
    for (int k = s.column_start[c]; k < s.column_start[c + 1]; ++k)
      s.a(s.row_index[k], c) = values[k];
  s.lu.compute(s.a);
  // Partial pivoting never stops at a zero pivot: it leaves it on U's
  // diagonal. The ratio of the smallest to the largest pivot is the cheap
  // (allocation-free) singularity test; Eigen's rcond() would allocate.
  const auto pivots = s.lu.matrixLU().diagonal().cwiseAbs();
  const double smallest = pivots.minCoeff();
  const double largest = pivots.maxCoeff();
  rcond_ = largest > 0.0 ? smallest / largest : 0.0;
  if (!std::isfinite(largest) || !(rcond_ > 1e-300)) {
    error_ = "the Newton tangent is singular (dense LU found a zero pivot; pivot ratio " +
             std::to_string(rcond_) + ")";
    rcond_ = 0.0;
    return false;
  }
  s.factored = true;
  return true;
}

void DenseLuSolver::solve(double* b) {
  Impl& s = *impl_;
  if (!s.factored) throw std::logic_error("DenseLuSolver::solve before a successful factor");
  s.rhs = Eigen::Map<const Eigen::VectorXd>(b, s.n);
  s.x = s.lu.solve(s.rhs);
  Eigen::Map<Eigen::VectorXd>(b, s.n) = s.x;
}

}  // namespace mh
