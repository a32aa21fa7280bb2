// The mass-orthogonal projections of the penalty formulation (Sect. 2.3,
// Eqs. 20-21; Bayo and Ledesma [3], Cuadrado et al. [9]): after a step has
// converged, the velocities and accelerations of the trapezoidal rule are
// projected so that they satisfy the constraints at velocity and acceleration
// level, within the same penalty approximation as the positions.
//
//   [W + dt^2/4 Phi_z^T alpha Phi_z] zd  = W zd'                                  Eq. (20)
//   [W + dt^2/4 Phi_z^T alpha Phi_z] zdd = W zdd' - dt^2/4 Phi_z^T alpha Phidot_z zd   Eq. (21)
//
// dt^2/4 is the trapezoidal rule's d x / d xdd: for any integrator of the host
// it is 1 / c_a with c_a = mh_step_coefficients.dxdd_dx_second, which the
// caller passes as `step_factor`.
//
// W: the paper's W = M + dt/2 C + dt^2/4 K, i.e. W = M' + C c_v / c_a + K / c_a
// (c_v = dxd_dx_second), with K and C from the host's mech_derivatives (ABI
// 2.1); or W = M' (option projection_matrix: mass). The caller forms W. With
// K and C, W is in general not symmetric: the matrix is factorized by LU.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

namespace mh_penalty {

using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstVectorMap = Eigen::Map<const Eigen::VectorXd>;

// The projection matrix [W + dt^2/4 Phi_z^T alpha Phi_z] (N x N), factorized
// once per step and applied to both
// right-hand sides. Sized once by resize(); factorize() and the projections do
// not allocate.
class Projector {
 public:
  // N coordinates, m constraint rows.
  void resize(int N, int m);

  // Factorizes [W + c Phi_z^T Phi_z] with c = step_factor alpha (step_factor:
  // the paper's dt^2/4, 1 / c_a), keeping W for the right-hand sides. W is N x N, phi_z m x N.
  // Returns false when the matrix is numerically singular (e.g. W singular and Phi_z rank
  // deficient in the same direction).
  bool factorize(const ConstMatrixMap& W, const ConstMatrixMap& phi_z, double step_factor,
                 double alpha);

  // Eq. (20): zd from the integrator's zd' (N each). zd may not alias zd_prime.
  void project_velocities(const Eigen::VectorXd& zd_prime, Eigen::VectorXd& zd);

  // Eq. (21): zdd from zdd' and Phidot_z zd evaluated at the projected zd (m).
  // zdd may not alias zdd_prime.
  void project_accelerations(const Eigen::VectorXd& zdd_prime, const ConstVectorMap& phi_dot_zd,
                             Eigen::VectorXd& zdd);

 private:
  double c_alpha_ = 0.0;   // dt^2/4 alpha = alpha / c_a
  Eigen::MatrixXd W_;      // N x N
  Eigen::MatrixXd phi_z_;  // m x N, of the last factorize()
  Eigen::MatrixXd A_;      // N x N, W + c_alpha Phi_z^T Phi_z
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::VectorXd rhs_;  // N
};

}  // namespace mh_penalty
