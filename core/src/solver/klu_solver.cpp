#include "monohydra/core/klu_solver.hpp"

#include <klu.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace mh {

// What depends on the pattern alone, read-only once made: shared by the
// solvers of one pattern.
struct KluSolver::Analysis {
  explicit Analysis(const SparsePattern& pattern)
      : n(pattern.size()), column_start(pattern.column_start()), row_index(pattern.row_index()) {
    klu_common common{};
    klu_defaults(&common);
    symbolic = klu_analyze(n, column_start.data(), row_index.data(), &common);
    if (symbolic == nullptr)
      throw std::runtime_error("KLU could not analyse the tangent's sparsity pattern (status " +
                               std::to_string(common.status) + ")");
  }
  ~Analysis() {
    klu_common common{};
    klu_defaults(&common);
    klu_free_symbolic(&symbolic, &common);
  }
  Analysis(const Analysis&) = delete;
  Analysis& operator=(const Analysis&) = delete;
  bool of(const SparsePattern& pattern) const {
    return n == pattern.size() && column_start == pattern.column_start() &&
           row_index == pattern.row_index();
  }
  int n = 0;
  std::vector<int> column_start;
  std::vector<int> row_index;
  klu_symbolic* symbolic = nullptr;
};

struct KluSolver::Impl {
  std::shared_ptr<const Analysis> analysis;
  klu_common common{};
  klu_numeric* numeric = nullptr;
};

KluSolver::KluSolver(const SparsePattern& pattern) : impl_(std::make_unique<Impl>()) {
  impl_->analysis = std::make_shared<const Analysis>(pattern);
  klu_defaults(&impl_->common);
}

KluSolver::KluSolver(const SparsePattern& pattern, const KluSolver& like)
    : impl_(std::make_unique<Impl>()) {
  impl_->analysis = like.impl_->analysis->of(pattern) ? like.impl_->analysis
                                                      : std::make_shared<const Analysis>(pattern);
  klu_defaults(&impl_->common);
}

KluSolver::~KluSolver() {
  if (impl_->numeric != nullptr) klu_free_numeric(&impl_->numeric, &impl_->common);
}

bool KluSolver::factor(const double* values) {
  auto* v = const_cast<double*>(values);  // KLU's API is not const-correct; it only reads
  Impl& s = *impl_;
  const Analysis& a = *s.analysis;
  auto* column_start = const_cast<int*>(a.column_start.data());  // read only, as v
  auto* row_index = const_cast<int*>(a.row_index.data());
  if (s.numeric != nullptr) {
    // Same pivots as last time: cheap. Fall back to a full factorization when
    // they no longer suit the matrix.
    if (klu_refactor(column_start, row_index, v, a.symbolic, s.numeric, &s.common) == 1 &&
        klu_rcond(a.symbolic, s.numeric, &s.common) == 1 && s.common.rcond >= rcond_refactor_) {
      rcond_ = s.common.rcond;
      return true;
    }
    klu_free_numeric(&s.numeric, &s.common);
  }
  s.numeric = klu_factor(column_start, row_index, v, a.symbolic, &s.common);
  ++full_factorizations_;
  if (s.numeric == nullptr) {
    error_ = s.common.status == KLU_SINGULAR
                 ? "the Newton tangent is singular (KLU found a zero pivot)"
                 : "KLU failed to factor the Newton tangent (status " +
                       std::to_string(s.common.status) + ")";
    rcond_ = 0.0;
    return false;
  }
  klu_rcond(a.symbolic, s.numeric, &s.common);
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
  klu_solve(s.analysis->symbolic, s.numeric, s.analysis->n, 1, b, &s.common);
}

}  // namespace mh
