// Mass-orthogonal projections of velocities and accelerations, Eqs. (20)-(21).
#include "projections.hpp"

#include "constraint_terms.hpp"

namespace mh_penalty {

void Projector::resize(int N, int m) {
  W_.setZero(N, N);
  phi_z_.setZero(m, N);
  A_.setZero(N, N);
  lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(N);  // sized now: compute() will not allocate
  rhs_.setZero(N);
}

bool Projector::factorize(const ConstMatrixMap& W, const ConstMatrixMap& phi_z, double step_factor,
                          double alpha) {
  c_alpha_ = step_factor * alpha;  // dt^2/4 alpha (trapezoidal), alpha / c_a in general
  W_ = W;
  phi_z_ = phi_z;
  // Eqs. (20)-(21), left-hand side: W + dt^2/4 Phi_z^T alpha Phi_z (one alpha
  // for every constraint, so alpha is a scalar).
  A_ = W_;
  add_penalty_matrix(A_, phi_z_, c_alpha_);
  if (!A_.allFinite()) return false;
  if (A_.rows() == 0) return true;  // no bodies (a model of subsystems only): nothing to project
  lu_.compute(A_);
  // The penalty term's scale (alpha dt^2/4 ~ 1e5 M) makes A's condition large
  // by design; only a numerically singular A is refused. The test is on U's
  // pivots, which partial pivoting leaves at hand: cond(U) >= max |u_ii| /
  // min |u_ii|, so a ratio below 1e-15 means a numerically singular matrix.
  // (Eigen's rcond() estimate costs two more solves and allocates its
  // work vectors: not at every step.)
  const auto pivots = lu_.matrixLU().diagonal().cwiseAbs();
  const double largest = pivots.maxCoeff();
  return pivots.allFinite() && largest > 0.0 && pivots.minCoeff() > 1e-15 * largest;
}

void Projector::project_velocities(const Eigen::VectorXd& zd_prime, Eigen::VectorXd& zd) {
  rhs_.noalias() = W_.lazyProduct(zd_prime);  // Eq. (20): W zd'
  zd = lu_.solve(rhs_);
}

void Projector::project_accelerations(const Eigen::VectorXd& zdd_prime,
                                      const ConstVectorMap& phi_dot_zd, Eigen::VectorXd& zdd) {
  // Eq. (21): W zdd' - dt^2/4 Phi_z^T alpha (Phidot_z zd). Scleronomic
  // constraints: no time-derivative terms (the paper's note under Eq. 21).
  rhs_.noalias() = W_.lazyProduct(zdd_prime);
  add_constraint_forces(rhs_, phi_z_, phi_dot_zd, -c_alpha_);
  zdd = lu_.solve(rhs_);
}

}  // namespace mh_penalty
