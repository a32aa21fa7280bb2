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

  // Dynamics (Eqs. 8-12).
  std::vector<Matrix6d> Mbar;      // Eq. (9)
  std::vector<Vector6d> Qbar;      // Eq. (10), with omega x gdot for omega x (omega x g)
  std::vector<Matrix6d> Mbar_sum;  // composite: body plus all descendants
  std::vector<Vector6d> Q_sum;     // composite of Qbar - Mbar Zdot0
  Eigen::MatrixXd M;               // M' (N x N), Eq. (12)
  Eigen::VectorXd Q;               // Q' (N), Eq. (12)

  // Copies of the coordinates the kinematics were last computed at.
  Eigen::VectorXd z;
  Eigen::VectorXd zd;
};

}  // namespace mh
