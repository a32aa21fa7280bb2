// Consistent initial accelerations and multipliers of the penalty formulation:
// the acceleration-level augmented Lagrangian problem at t0 (Bayo and
// Ledesma [3]; Eq. 18 differentiated twice),
//
//   (M' + Phi_z^T alpha Phi_z) zdd = Q' - Phi_z^T (alpha Phidot_z zd + lambda)
//   lambda <- lambda + alpha (Phi_z zdd + Phidot_z zd)
//
// iterated until the constraint accelerations Phi_z zdd + Phidot_z zd vanish.
// Unlike the KKT system [M' Phi_z^T; Phi_z 0], the matrix stays positive
// definite when constraints are redundant (Phi_z rank deficient), and lambda
// converges to a set of multipliers whose forces Phi_z^T lambda are the
// constraint forces.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace mh_penalty {

struct AccelerationSolve {
  int iterations = 0;       // augmented Lagrangian updates of lambda
  double violation = 0.0;   // ||Phi_z zdd + Phidot_z zd||_inf at the end (rad/s^2 or m/s^2)
  double bound = 0.0;       // the violation it had to reach
  double correction = 0.0;  // |last change of zdd|_inf (rad/s^2 or m/s^2)
  bool converged = false;
  bool positive_definite = true;  // false: M' + Phi_z^T alpha Phi_z could not be factorized
};

// M: N x N, Q: N, phi_z: m x N, phi_dot_zd: m (column-major, as the host
// returns them). Writes zdd (N) and lambda (m), which must already have their
// sizes; lambda's input value is the starting guess.
AccelerationSolve solve_initial_accelerations(const Eigen::Map<const Eigen::MatrixXd>& M,
                                              const Eigen::Map<const Eigen::VectorXd>& Q,
                                              const Eigen::Map<const Eigen::MatrixXd>& phi_z,
                                              const Eigen::Map<const Eigen::VectorXd>& phi_dot_zd,
                                              double alpha, Eigen::VectorXd& zdd,
                                              Eigen::VectorXd& lambda);

}  // namespace mh_penalty
