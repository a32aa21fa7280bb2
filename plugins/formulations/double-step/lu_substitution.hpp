// Solves with the partial-pivoting LU of Phi_z^d (P A = L U) by plain forward
// and back substitution, in place and allocation-free. Eigen's own
// PartialPivLU::solve does the same, but for a vector right-hand side its
// triangular solver keeps a fallback heap path that clang-analyzer reports as
// a potential leak; r is small (the dependent coordinates), so nothing is lost.
#pragma once

#include "eigen.hpp"

namespace mh::double_step {

// b := A^{-1} b; `scratch` has b's size.
inline void lu_solve_in_place(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu,
                              Eigen::Ref<Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> scratch) {
  const Eigen::MatrixXd& LU = lu.matrixLU();
  const auto& P = lu.permutationP().indices();
  const Eigen::Index n = LU.rows();
  for (Eigen::Index i = 0; i < n; ++i) scratch[P[i]] = b[i];  // P b
  for (Eigen::Index i = 0; i < n; ++i) {                      // L y = P b, unit diagonal
    double v = scratch[i];
    for (Eigen::Index j = 0; j < i; ++j) v -= LU(i, j) * scratch[j];
    scratch[i] = v;
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {  // U x = y
    double v = scratch[i];
    for (Eigen::Index j = i + 1; j < n; ++j) v -= LU(i, j) * b[j];
    b[i] = v / LU(i, i);
  }
}

// b := A^{-T} b (A^T = U^T L^T P); `scratch` has b's size.
inline void lu_solve_transpose_in_place(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu,
                                        Eigen::Ref<Eigen::VectorXd> b,
                                        Eigen::Ref<Eigen::VectorXd> scratch) {
  const Eigen::MatrixXd& LU = lu.matrixLU();
  const auto& P = lu.permutationP().indices();
  const Eigen::Index n = LU.rows();
  for (Eigen::Index i = 0; i < n; ++i) {  // U^T w = b
    double v = b[i];
    for (Eigen::Index j = 0; j < i; ++j) v -= LU(j, i) * scratch[j];
    scratch[i] = v / LU(i, i);
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {  // L^T u = w, unit diagonal
    double v = scratch[i];
    for (Eigen::Index j = i + 1; j < n; ++j) v -= LU(j, i) * scratch[j];
    scratch[i] = v;
  }
  for (Eigen::Index i = 0; i < n; ++i) b[i] = scratch[P[i]];  // y = P^T u
}

}  // namespace mh::double_step
