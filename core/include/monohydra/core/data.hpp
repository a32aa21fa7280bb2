// The per-run workspace of the semirecursive algorithms: every buffer they
// write, sized once from a Model, so that nothing allocates inside a time step.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/model.hpp"

namespace mh {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct Data {
  explicit Data(const Model& model);

  // Kinematics (Eqs. 1-7), per body, world frame.
  std::vector<Eigen::Matrix3d> R_W_B;  // orientation of body frame
  std::vector<Eigen::Vector3d> o_W;    // origin of body frame (the joint point)
  std::vector<Eigen::Vector3d> u_W;    // joint axis
  std::vector<Eigen::Vector3d> g_W;    // centre of mass (g_j)
  std::vector<Vector6d> Z;             // [sdot; omega], Eq. (1)
  std::vector<Vector6d> b;             // Eq. (2)
  std::vector<Vector6d> d;             // Eq. (3)
  std::vector<Vector6d> Zdot0;         // Zdot with zdd = 0: T Rdot_d zd, Eq. (5)
  // Zdot is the plain time derivative of Z, so its first half is not the
  // acceleration of the body point at the origin (that adds omega x sdot);
  // use point_bias_acceleration() for points.

  // Applied loads, per body: force and moment about the centre of mass, world
  // frame. Reset (to gravity) by reset_applied_forces(); point forces add here.
  std::vector<Eigen::Vector3d> f_W;
  std::vector<Eigen::Vector3d> tau_W;

  // Dynamics (Eqs. 8-12). Mbar_j of Eq. (9) is [m I, -c~; c~, I_O] with
  // c = m g and I_O = J - m g~ g~ (the inertia about the world origin), and
  // a sum of such matrices keeps the form: the composites below hold it as
  // (mass, c, I_O), 13 numbers, instead of 36.
  std::vector<double> m_sum;           // composite mass: body plus all descendants
  std::vector<Eigen::Vector3d> c_sum;  // composite first moment, sum of m g
  std::vector<Eigen::Matrix3d> I_sum;  // composite inertia about the world origin
  std::vector<Vector6d> Q_sum;         // composite of Qbar - Mbar Zdot0 (Eqs. 10, 11)
  std::vector<Vector6d> A_zdd;         // T R_d zdd: inverse_dynamics' accelerations
  Eigen::MatrixXd M;                   // M' (N x N), Eq. (12)
  Eigen::VectorXd Q;                   // Q' (N), Eq. (12)

  // Copies of the coordinates the kinematics were last computed at.
  Eigen::VectorXd z;
  Eigen::VectorXd zd;
};

}  // namespace mh
