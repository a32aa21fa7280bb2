// Eqs. (13)-(17) of coordinate partitioning, on preallocated buffers.
#include "velocity_transformation.hpp"

#include "lu_substitution.hpp"

namespace mh::double_step {

void VelocityTransformation::resize(int N, int r) {
  const int f = N - r;
  N_ = N;
  W_.setZero(r, f);
  R_z_.setZero(N, f);
  Rdot_zd_.setZero(N);
  rhs_.setZero(r);
  sol_.setZero(r);
  vi_.setZero(f);
  MR_.setZero(N, f);
  force_.setZero(N);
  M_reduced_.setZero(f, f);
  Q_reduced_.setZero(f);
}

void VelocityTransformation::set_partition(const Partition& p) {
  R_z_.setZero();
  for (size_t k = 0; k < p.independent.size(); ++k)
    R_z_(p.independent[k], static_cast<Eigen::Index>(k)) = 1.0;  // Eq. (14): the I block
}

void VelocityTransformation::rates(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu_d,
                                   const Eigen::MatrixXd& phi_z_i, const Partition& p,
                                   Eigen::VectorXd& zd) {
  const Eigen::Index f = W_.cols();
  for (Eigen::Index k = 0; k < f; ++k) {  // W = (Phi_z^d)^{-1} Phi_z^i, column by column
    sol_ = phi_z_i.col(k);
    lu_solve_in_place(lu_d, sol_, rhs_);
    W_.col(k) = sol_;
  }
  for (Eigen::Index k = 0; k < f; ++k) vi_[k] = zd[p.independent[static_cast<size_t>(k)]];
  sol_.noalias() = W_.lazyProduct(vi_);
  for (size_t a = 0; a < p.dependent.size(); ++a) {
    const auto row = static_cast<Eigen::Index>(a);
    R_z_.row(p.dependent[a]) = -W_.row(row);  // Eq. (14)
    zd[p.dependent[a]] = -sol_[row];          // Eq. (13)
  }
}

void VelocityTransformation::velocity_term(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu_d,
                                           const double* phi_dot_zd, const Partition& p) {
  for (size_t a = 0; a < p.rows.size(); ++a)
    rhs_[static_cast<Eigen::Index>(a)] = phi_dot_zd[p.rows[a]];
  lu_solve_in_place(lu_d, rhs_, sol_);
  Rdot_zd_.setZero();
  for (size_t a = 0; a < p.dependent.size(); ++a)
    Rdot_zd_[p.dependent[a]] = -rhs_[static_cast<Eigen::Index>(a)];
}

void VelocityTransformation::reduce(const double* M, const double* Q) {
  const Eigen::Map<const Eigen::MatrixXd> M_prime(M, N_, N_);
  const Eigen::Map<const Eigen::VectorXd> Q_prime(Q, N_);
  MR_.noalias() = M_prime.lazyProduct(R_z_);
  M_reduced_.noalias() = R_z_.transpose().lazyProduct(MR_);  // Eq. (17): M''
  force_ = Q_prime;
  force_.noalias() -= M_prime.lazyProduct(Rdot_zd_);
  Q_reduced_.noalias() = R_z_.transpose().lazyProduct(force_);  // Eq. (17): Q''
}

void VelocityTransformation::accelerations(const Partition& p, Eigen::VectorXd& zdd) const {
  // zdd = R_z zdd^i + Rdot_z zd^i (Eq. 15), written on the dependent entries
  // only: on the independent ones R_z is the identity and Rdot_z zd^i is 0.
  for (size_t a = 0; a < p.dependent.size(); ++a) {
    double v = Rdot_zd_[p.dependent[a]];
    for (size_t k = 0; k < p.independent.size(); ++k)
      v += R_z_(p.dependent[a], static_cast<Eigen::Index>(k)) * zdd[p.independent[k]];
    zdd[p.dependent[a]] = v;
  }
}

}  // namespace mh::double_step
