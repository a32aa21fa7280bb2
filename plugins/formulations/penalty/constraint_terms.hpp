// The two constraint terms every equation of the penalty formulation carries
// (Eqs. 18-21): generalized constraint forces Phi_z^T v and the penalty
// matrix Phi_z^T alpha Phi_z.
//
// Both are written as dot products of Phi_z's columns instead of Eigen
// transposed products: no temporaries (Eigen's transposed matrix-vector
// product declares a stack-or-heap buffer, which the static analyser in CI
// reports as a possible leak), an exactly symmetric matrix, and m is small.
#pragma once

#include <Eigen/Core>

namespace mh_penalty {

// out += scale Phi_z^T v, with Phi_z m x N (column-major), v m, out N.
inline void add_constraint_forces(Eigen::Ref<Eigen::VectorXd> out,
                                  const Eigen::Ref<const Eigen::MatrixXd>& phi_z,
                                  const Eigen::Ref<const Eigen::VectorXd>& v, double scale) {
  for (Eigen::Index j = 0; j < phi_z.cols(); ++j) out[j] += scale * phi_z.col(j).dot(v);
}

// A += scale Phi_z^T Phi_z, with A N x N and Phi_z m x N.
inline void add_penalty_matrix(Eigen::Ref<Eigen::MatrixXd> A,
                               const Eigen::Ref<const Eigen::MatrixXd>& phi_z, double scale) {
  for (Eigen::Index j = 0; j < phi_z.cols(); ++j) {
    A(j, j) += scale * phi_z.col(j).squaredNorm();
    for (Eigen::Index i = j + 1; i < phi_z.cols(); ++i) {
      const double a = scale * phi_z.col(i).dot(phi_z.col(j));
      A(i, j) += a;
      A(j, i) += a;
    }
  }
}

}  // namespace mh_penalty
