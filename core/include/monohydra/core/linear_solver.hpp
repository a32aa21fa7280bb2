// The linear solver of the shared Newton step, behind a small interface (as
// SUNDIALS separates its linear solvers from the nonlinear one): the Newton
// loop hands it the tangent's values in the run's fixed sparsity pattern and
// right-hand sides; it owns the factorization. Three are shipped: KLU
// (klu_solver.hpp, the default), UMFPACK (umfpack_solver.hpp) and dense LU
// (dense_lu_solver.hpp, for small systems); the model file chooses one
// (`solver: {linear: ...}`).
#pragma once

#include <memory>
#include <string>

#include "monohydra/core/sparse_pattern.hpp"

namespace mh {

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // Factors the matrix with the pattern's layout and these values. Returns
  // false when it is singular; error() then says why.
  virtual bool factor(const double* values) = 0;
  // Solves A x = b in place (b has the pattern's size). Requires a successful factor().
  virtual void solve(double* b) = 0;
  virtual const std::string& error() const = 0;
};

enum class LinearSolverKind { klu, umfpack, dense };
// "klu", "umfpack", "dense": the names the model file uses.
// Inline: the model-file parser (and its fuzzer, which links no solver) names kinds too.
inline const char* to_string(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::klu:
      return "klu";
    case LinearSolverKind::umfpack:
      return "umfpack";
    case LinearSolverKind::dense:
      return "dense";
  }
  return "?";
}

// The shipped solver of that kind for `pattern` (its symbolic analysis done here).
std::unique_ptr<LinearSolver> make_linear_solver(const SparsePattern& pattern,
                                                 LinearSolverKind kind = LinearSolverKind::klu);

}  // namespace mh
