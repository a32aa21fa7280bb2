#include "monohydra/core/klu_solver.hpp"

#include <klu.h>

#include <stdexcept>
#include <vector>

namespace mh {

struct KluSolver::Impl {
  int n = 0;
  std::vector<int> column_start;
  std::vector<int> row_index;
  klu_common common{};
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
};

KluSolver::KluSolver(const SparsePattern& pattern) : impl_(std::make_unique<Impl>()) {
  impl_->n = pattern.size();
  impl_->column_start = pattern.column_start();
  impl_->row_index = pattern.row_index();
  klu_defaults(&impl_->common);
  impl_->symbolic =
      klu_analyze(impl_->n, impl_->column_start.data(), impl_->row_index.data(), &impl_->common);
  if (impl_->symbolic == nullptr)
    throw std::runtime_error("KLU could not analyse the tangent's sparsity pattern (status " +
                             std::to_string(impl_->common.status) + ")");
}

KluSolver::~KluSolver() {
  if (impl_->numeric != nullptr) klu_free_numeric(&impl_->numeric, &impl_->common);
  if (impl_->symbolic != nullptr) klu_free_symbolic(&impl_->symbolic, &impl_->common);
}

bool KluSolver::factor(const double* values) {
  auto* v = const_cast<double*>(values);  // KLU's API is not const-correct; it only reads
  Impl& s = *impl_;
  if (s.numeric != nullptr) {
    // Same pivots as last time: cheap. Fall back to a full factorization when
    // they no longer suit the matrix.
    if (klu_refactor(s.column_start.data(), s.row_index.data(), v, s.symbolic, s.numeric,
                     &s.common) == 1 &&
        klu_rcond(s.symbolic, s.numeric, &s.common) == 1 && s.common.rcond >= rcond_refactor_) {
      rcond_ = s.common.rcond;
      return true;
    }
    klu_free_numeric(&s.numeric, &s.common);
  }
  s.numeric = klu_factor(s.column_start.data(), s.row_index.data(), v, s.symbolic, &s.common);
  ++full_factorizations_;
  if (s.numeric == nullptr) {
    error_ = s.common.status == KLU_SINGULAR
                 ? "the Newton tangent is singular (KLU found a zero pivot)"
                 : "KLU failed to factor the Newton tangent (status " +
                       std::to_string(s.common.status) + ")";
    rcond_ = 0.0;
    return false;
  }
  klu_rcond(s.symbolic, s.numeric, &s.common);
  rcond_ = s.common.rcond;
  if (!(rcond_ > 1e-300)) {
    error_ =
        "the Newton tangent is numerically singular (KLU rcond " + std::to_string(rcond_) + ")";
    klu_free_numeric(&s.numeric, &s.common);
    return false;
  }
  return true;
}

void KluSolver::solve(double* b) {
  Impl& s = *impl_;
  if (s.numeric == nullptr) throw std::logic_error("KluSolver::solve before a successful factor");
  klu_solve(s.symbolic, s.numeric, s.n, 1, b, &s.common);
}

}  // namespace mh
