#include "monohydra/core/umfpack_solver.hpp"

#include <umfpack.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace mh {

struct UmfpackSolver::Impl {
  int n = 0;
  std::vector<int> column_start;
  std::vector<int> row_index;
  std::vector<double> values;  // the factored matrix (UMFPACK's refinement reads it)
  std::vector<double> b;       // the right-hand side (UMFPACK solves out of place)
  double control[UMFPACK_CONTROL]{};
  double info[UMFPACK_INFO]{};
  void* symbolic = nullptr;
  void* numeric = nullptr;
};

UmfpackSolver::UmfpackSolver(const SparsePattern& pattern) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.n = pattern.size();
  s.column_start = pattern.column_start();
  s.row_index = pattern.row_index();
  s.values.assign(s.row_index.size(), 0.0);
  s.b.assign(static_cast<size_t>(s.n), 0.0);
  umfpack_di_defaults(s.control);
  // The pattern alone is analysed: ones in every slot stand for the values.
  std::vector<double> ones(s.row_index.size(), 1.0);
  const int status = umfpack_di_symbolic(s.n, s.n, s.column_start.data(), s.row_index.data(),
                                         ones.data(), &s.symbolic, s.control, s.info);
  if (status != UMFPACK_OK)
    throw std::runtime_error("UMFPACK could not analyse the tangent's sparsity pattern (status " +
                             std::to_string(status) + ")");
}

UmfpackSolver::~UmfpackSolver() {
  if (impl_->numeric != nullptr) umfpack_di_free_numeric(&impl_->numeric);
  if (impl_->symbolic != nullptr) umfpack_di_free_symbolic(&impl_->symbolic);
}

bool UmfpackSolver::factor(const double* values) {
  Impl& s = *impl_;
  if (s.numeric != nullptr) umfpack_di_free_numeric(&s.numeric);
  std::copy(values, values + s.values.size(), s.values.begin());
  const int status = umfpack_di_numeric(s.column_start.data(), s.row_index.data(), s.values.data(),
                                        s.symbolic, &s.numeric, s.control, s.info);
  rcond_ = s.info[UMFPACK_RCOND];
  if (status == UMFPACK_OK && rcond_ > 1e-300) return true;
  error_ =
      status == UMFPACK_WARNING_singular_matrix || status == UMFPACK_OK
          ? "the Newton tangent is singular (UMFPACK rcond " + std::to_string(rcond_) + ")"
          : "UMFPACK failed to factor the Newton tangent (status " + std::to_string(status) + ")";
  if (s.numeric != nullptr) umfpack_di_free_numeric(&s.numeric);
  rcond_ = 0.0;
  return false;
}

void UmfpackSolver::solve(double* b) {
  Impl& s = *impl_;
  if (s.numeric == nullptr)
    throw std::logic_error("UmfpackSolver::solve before a successful factor");
  std::copy(b, b + s.n, s.b.begin());
  umfpack_di_solve(UMFPACK_A, s.column_start.data(), s.row_index.data(), s.values.data(), b,
                   s.b.data(), s.numeric, s.control, s.info);
}

}  // namespace mh
