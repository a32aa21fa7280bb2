// SuiteSparse UMFPACK behind the LinearSolver interface: the symbolic
// analysis once for the run's fixed pattern (umfpack_di_symbolic), a numeric
// factorization per factor(). A general multifrontal LU, an alternative to
// KLU's for patterns with large dense blocks.
#pragma once

#include <memory>
#include <string>

#include "monohydra/core/linear_solver.hpp"
#include "monohydra/core/sparse_pattern.hpp"

namespace mh {

class UmfpackSolver final : public LinearSolver {
 public:
  explicit UmfpackSolver(const SparsePattern& pattern);  // umfpack_di_symbolic
  ~UmfpackSolver() override;
  UmfpackSolver(const UmfpackSolver&) = delete;
  UmfpackSolver& operator=(const UmfpackSolver&) = delete;

  bool factor(const double* values) override;
  void solve(double* b) override;
  const std::string& error() const override { return error_; }
  double last_rcond() const { return rcond_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double rcond_ = 0.0;
  std::string error_;
};

}  // namespace mh
