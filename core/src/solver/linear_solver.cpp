// The linear solvers the model file may choose (`solver: {linear: ...}`),
// behind the one interface the Newton loop uses.
#include "monohydra/core/linear_solver.hpp"

#include "monohydra/core/dense_lu_solver.hpp"
#include "monohydra/core/klu_solver.hpp"
#include "monohydra/core/umfpack_solver.hpp"

namespace mh {

LinearSolverKind resolve_linear_solver(const SparsePattern& pattern, LinearSolverKind kind) {
  if (kind != LinearSolverKind::automatic) return kind;
  const double n = pattern.size();
  const double density = n > 0 ? pattern.nonzeros() / (n * n) : 1.0;
  return density > kAutoDenseDensity ? LinearSolverKind::dense : LinearSolverKind::klu;
}

std::unique_ptr<LinearSolver> make_linear_solver(const SparsePattern& pattern,
                                                 LinearSolverKind kind, const LinearSolver* like) {
  switch (resolve_linear_solver(pattern, kind)) {
    case LinearSolverKind::umfpack:
      return std::make_unique<UmfpackSolver>(pattern);
    case LinearSolverKind::dense:
      return std::make_unique<DenseLuSolver>(pattern);
    case LinearSolverKind::klu:
    case LinearSolverKind::automatic:
      break;
  }
  if (const auto* klu = dynamic_cast<const KluSolver*>(like); klu != nullptr)
    return std::make_unique<KluSolver>(pattern, *klu);
  return std::make_unique<KluSolver>(pattern);
}

}  // namespace mh
