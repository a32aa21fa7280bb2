// The sparse linear solver of the shared Newton step: SuiteSparse KLU, with
// the symbolic analysis done once for the run's fixed pattern and numeric
// refactorization after that (as SUNDIALS' KLU wrapper does).
#pragma once

#include <memory>
#include <string>

#include "monohydra/core/linear_solver.hpp"
#include "monohydra/core/sparse_pattern.hpp"

namespace mh {

class KluSolver final : public LinearSolver {
 public:
  explicit KluSolver(const SparsePattern& pattern);  // klu_analyze
  // For the same pattern as `like`'s: its analysis (the pattern's arrays and
  // KLU's symbolic ordering) shared, not made again, since KLU only reads it
  // when factoring and solving: the runs of a batch analyse their tangent
  // once. A pattern that differs is analysed anew.
  KluSolver(const SparsePattern& pattern, const KluSolver& like);
  ~KluSolver() override;
  KluSolver(const KluSolver&) = delete;
  KluSolver& operator=(const KluSolver&) = delete;

  // Factors the matrix with the pattern's layout and these values. Refactors
  // when a factorization exists, and factors anew (new pivots) when the
  // reciprocal condition estimate falls below `rcond_refactor`. Returns false
  // when the matrix is singular; error() then says why.
  bool factor(const double* values) override;
  // Solves A x = b in place (b has size n). Requires a successful factor().
  void solve(double* b) override;

  double last_rcond() const { return rcond_; }
  const std::string& error() const override { return error_; }
  int full_factorizations() const { return full_factorizations_; }

 private:
  struct Analysis;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double rcond_ = 0.0;
  double rcond_refactor_ = 1e-12;
  std::string error_;
  int full_factorizations_ = 0;
};

}  // namespace mh
