// Open-loop semirecursive dynamics (Sect. 2.1, Eqs. 8-12): M' zdd = Q'.
#pragma once

#include <Eigen/Core>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// Sets every body's applied load to its weight m_j * gravity at the centre of
// mass. Valid after forward_kinematics.
void reset_applied_forces(const Model& model, Data& data);

// Adds a force F_W (world frame, N) acting at world point p_W of `body`
// (ignored for the ground). Valid after forward_kinematics.
void apply_point_force(Data& data, int body, const Eigen::Vector3d& p_W,
                       const Eigen::Vector3d& F_W);
// Adds a pure moment (world frame, N m) to `body`.
void apply_body_moment(Data& data, int body, const Eigen::Vector3d& tau_W);

// Body j's Mbar_j (Eq. 9) at the world origin, [m I, -c~; c~, I_O] with
// c = m g and I_O = J - m g~ g~, from the kinematics in data.
Matrix6d body_mass_matrix(const Model& model, const Data& data, int j);

// M' = R_d^T T^T Mbar T R_d and Q' = R_d^T T^T (Qbar - Mbar T Rdot_d zd)
// (Eq. 12) into data.M and data.Q, from the kinematics and applied loads in data.
void mass_matrix_and_forces(const Model& model, Data& data);

// r = M' zdd - Q' (Eq. 12) in O(N), without forming M': each body's Mbar_j
// times its acceleration from zdd (T R_d zdd) less its Qbar_j - Mbar_j Zdot0_j,
// summed over subtrees and projected on each joint's b (the recursion of
// Newton-Euler inverse dynamics in the semirecursive form). Uses data's
// m_sum, c_sum, I_sum, Q_sum and A_zdd as workspace: data.M and data.Q are
// not touched (they keep the last mass_matrix_and_forces).
void inverse_dynamics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& zdd,
                      Eigen::Ref<Eigen::VectorXd> r);

// Kinetic energy 1/2 zd^T M' zd, computed body by body from Eq. (6).
double kinetic_energy(const Model& model, const Data& data);
// Gravitational potential energy -sum m_j gravity . g_j (zero at the world origin).
double potential_energy(const Model& model, const Data& data);

}  // namespace mh
