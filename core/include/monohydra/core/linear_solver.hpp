// The linear solver of the shared Newton step, behind a small interface (as
// SUNDIALS separates its linear solvers from the nonlinear one): the Newton
// loop hands it the tangent's values in the run's fixed sparsity pattern and
// right-hand sides; it owns the factorization. Three are shipped: KLU
// (klu_solver.hpp, the default), UMFPACK (umfpack_solver.hpp) and dense LU
// (dense_lu_solver.hpp, for small systems); the model file chooses one
// (`solver: {linear: ...}`), or `auto`: dense LU for a dense pattern, KLU
// otherwise (make_linear_solver).
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

enum class LinearSolverKind { klu, umfpack, dense, automatic };
// "klu", "umfpack", "dense", "auto": the names the model file uses.
// Inline: the model-file parser (and its fuzzer, which links no solver) names kinds too.
inline const char* to_string(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::klu:
      return "klu";
    case LinearSolverKind::umfpack:
      return "umfpack";
    case LinearSolverKind::dense:
      return "dense";
    case LinearSolverKind::automatic:
      return "auto";
  }
  return "?";
}

// Above this share of nonzeros `auto` takes dense LU: a blocked dense
// factorization beats KLU's sparse one on a (nearly) full matrix (measured on
// the bench's chains, docs/performance.md).
constexpr double kAutoDenseDensity = 0.5;

// The kind `auto` stands for on `pattern`; any other kind as it is.
LinearSolverKind resolve_linear_solver(const SparsePattern& pattern, LinearSolverKind kind);

// The shipped solver of that kind for `pattern` (its symbolic analysis done
// here, or shared with `like`'s when that is a KLU solver of the same
// pattern: klu_solver.hpp).
std::unique_ptr<LinearSolver> make_linear_solver(const SparsePattern& pattern,
                                                 LinearSolverKind kind = LinearSolverKind::klu,
                                                 const LinearSolver* like = nullptr);

}  // namespace mh
