// The velocity transformation of coordinate partitioning, Eqs. (13)-(17):
// zd = R_z zd^i, zdd = R_z zdd^i + Rdot_z zd^i, and the reduced equations of
// motion M'' zdd^i = Q'' with M'' = R_z^T M' R_z, Q'' = R_z^T (Q' - M' Rdot_z zd^i).
#pragma once

#include "coordinate_partition.hpp"
#include "eigen.hpp"

namespace mh::double_step {

class VelocityTransformation {
 public:
  // Sizes every buffer: N coordinates, r dependent, f = N - r independent.
  void resize(int N, int r);
  // A new partition: R_z's independent rows become the identity (Eq. 14).
  void set_partition(const Partition& p);

  // Eqs. (13)-(14): R_z from the LU of Phi_z^d and Phi_z^i at z, and the
  // dependent rates zd[dependent] = -(Phi_z^d)^{-1} Phi_z^i zd[independent].
  void rates(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu_d, const Eigen::MatrixXd& phi_z_i,
             const Partition& p, Eigen::VectorXd& zd);

  // Rdot_z zd^i: the accelerations zdd of Eq. (15) when zdd^i = 0, i.e.
  // -(Phi_z^d)^{-1} (Phi_z_dot zd) on the dependent coordinates (kept rows of
  // phi_dot_zd, m entries, at the full zd) and 0 on the independent ones.
  void velocity_term(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu_d, const double* phi_dot_zd,
                     const Partition& p);

  // Eq. (17): M'' = R_z^T M' R_z, Q'' = R_z^T (Q' - M' Rdot_z zd^i); M and Q
  // are the host's N x N (column-major) and N arrays.
  void reduce(const double* M, const double* Q);

  // Eq. (15): zdd[dependent] = R_z^d zdd[independent] + (Rdot_z zd^i)^d.
  void accelerations(const Partition& p, Eigen::VectorXd& zdd) const;

  const Eigen::MatrixXd& R_z() const { return R_z_; }              // N x f, Eq. (14)
  const Eigen::MatrixXd& M_reduced() const { return M_reduced_; }  // M'', f x f
  const Eigen::VectorXd& Q_reduced() const { return Q_reduced_; }  // Q'', f

 private:
  int N_ = 0;
  Eigen::MatrixXd W_;          // r x f: (Phi_z^d)^{-1} Phi_z^i, so R_z^d = -W
  Eigen::MatrixXd R_z_;        // N x f, Eq. (14)
  Eigen::VectorXd Rdot_zd_;    // N: Rdot_z zd^i
  Eigen::VectorXd rhs_, sol_;  // r
  Eigen::VectorXd vi_;         // f
  Eigen::MatrixXd MR_;         // N x f: M' R_z
  Eigen::VectorXd force_;      // N: Q' - M' Rdot_z zd^i
  Eigen::MatrixXd M_reduced_;  // f x f
  Eigen::VectorXd Q_reduced_;  // f
};

}  // namespace mh::double_step
