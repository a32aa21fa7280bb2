// Open-loop semirecursive kinematics, base to leaves (Sect. 2.1, Eqs. 1-7).
#pragma once

#include <Eigen/Core>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// Positions, orientations, velocities Z_j, vectors b_j and d_j and the
// velocity-product accelerations Zdot0_j of every body at (z, zd).
// Expected sizes: z and zd of model.num_coordinates(). Throws std::invalid_argument
// ("expected N, got M") on a size mismatch. Does not allocate.
void forward_kinematics(const Model& model, Data& data, const Eigen::VectorXd& z,
                        const Eigen::VectorXd& zd);

// The velocity level of forward_kinematics alone: Z_j, d_j and Zdot0_j at new
// rates zd, the positions, orientations and b_j kept from the last
// forward_kinematics (at data.z, which must be where they were computed). The
// same values, bit for bit, as forward_kinematics(model, data, data.z, zd),
// without rebuilding the rotations. Same checks; does not allocate.
void forward_velocities(const Model& model, Data& data, const Eigen::VectorXd& zd);

// World position and velocity of a point fixed on a body (ground: the point itself,
// zero velocity). Valid after forward_kinematics.
Eigen::Vector3d point_position(const Data& data, const BodyPoint& point);
Eigen::Vector3d point_velocity(const Data& data, const BodyPoint& point);
// Acceleration of the point for zdd = 0 (the velocity-product term).
Eigen::Vector3d point_bias_acceleration(const Data& data, const BodyPoint& point);
// Angular velocity of a body (zero for the ground).
Eigen::Vector3d body_angular_velocity(const Data& data, int body);
Eigen::Matrix3d body_rotation(const Data& data, int body);

// Jacobian of the point's world velocity with respect to zd (3 x N): column j is
// the velocity of the point per unit zd_j. Writes into J, which must be 3 x N.
void point_jacobian(const Model& model, const Data& data, const BodyPoint& point,
                    Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> J);
// Jacobian of the body's angular velocity with respect to zd (3 x N).
void angular_jacobian(const Model& model, const Data& data, int body,
                      Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> J);

// True when body `ancestor` is on the path from the ground to `body` (or equal).
bool is_ancestor_or_self(const Model& model, int ancestor, int body);

}  // namespace mh
