#include "monohydra/core/data.hpp"

namespace mh {

Data::Data(const Model& model) {
  const auto nb = static_cast<std::size_t>(model.num_bodies());
  const Eigen::Index n = model.num_coordinates();
  // Every buffer the algorithms write is sized here, once, so that
  // forward_kinematics and mass_matrix_and_forces never allocate.
  R_W_B.assign(nb, Eigen::Matrix3d::Identity());
  o_W.assign(nb, Eigen::Vector3d::Zero());
  u_W.assign(nb, Eigen::Vector3d::Zero());
  g_W.assign(nb, Eigen::Vector3d::Zero());
  Z.assign(nb, Vector6d::Zero());
  b.assign(nb, Vector6d::Zero());
  d.assign(nb, Vector6d::Zero());
  Zdot0.assign(nb, Vector6d::Zero());
  f_W.assign(nb, Eigen::Vector3d::Zero());
  tau_W.assign(nb, Eigen::Vector3d::Zero());
  m_sum.assign(nb, 0.0);
  c_sum.assign(nb, Eigen::Vector3d::Zero());
  I_sum.assign(nb, Eigen::Matrix3d::Zero());
  Q_sum.assign(nb, Vector6d::Zero());
  A_zdd.assign(nb, Vector6d::Zero());
  M = Eigen::MatrixXd::Zero(n, n);
  Q = Eigen::VectorXd::Zero(n);
  z = Eigen::VectorXd::Zero(n);
  zd = Eigen::VectorXd::Zero(n);
}

}  // namespace mh
