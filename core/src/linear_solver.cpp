// The linear solvers the model file may choose (`solver: {linear: ...}`),
// behind the one interface the Newton loop uses.
#include "monohydra/core/linear_solver.hpp"

#include "monohydra/core/dense_lu_solver.hpp"
#include "monohydra/core/klu_solver.hpp"
#include "monohydra/core/umfpack_solver.hpp"

namespace mh {

std::unique_ptr<LinearSolver> make_linear_solver(const SparsePattern& pattern,
                                                 LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::umfpack:
      return std::make_unique<UmfpackSolver>(pattern);
    case LinearSolverKind::dense:
      return std::make_unique<DenseLuSolver>(pattern);
    case LinearSolverKind::klu:
      break;
  }
  return std::make_unique<KluSolver>(pattern);
}

}  // namespace mh
