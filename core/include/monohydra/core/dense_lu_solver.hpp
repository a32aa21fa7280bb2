// Dense LU with partial pivoting (Eigen) behind the LinearSolver interface:
// for small systems (the case studies' 9 to 12 unknowns), where a sparse
// solver's bookkeeping costs more than the arithmetic it saves. The matrix
// and its factors are sized once, at construction.
#pragma once

#include <memory>
#include <string>

#include "monohydra/core/linear_solver.hpp"
#include "monohydra/core/sparse_pattern.hpp"

namespace mh {

class DenseLuSolver final : public LinearSolver {
 public:
  explicit DenseLuSolver(const SparsePattern& pattern);
  ~DenseLuSolver() override;
  DenseLuSolver(const DenseLuSolver&) = delete;
  DenseLuSolver& operator=(const DenseLuSolver&) = delete;

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
