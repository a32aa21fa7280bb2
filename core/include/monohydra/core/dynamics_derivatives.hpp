// Analytic derivatives of the open-loop semirecursive dynamics (Sect. 2.1,
// Eqs. 1-12): the tangent of the residual M'(z) zdd - Q'(z, zd) that an implicit
// integrator's Newton iteration needs, without finite differences. The
// recursion differentiates Z, Zdot, R_W_B and the positions through the tree, as
// Pinocchio's RNEA derivatives do; see core/src/algorithms/motion_variation.hpp.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// A force F_W (world frame, N) on body point.body at that body point, as
// apply_point_force applies it, with its derivatives with respect to the
// point's world position and velocity and, for a force between two points
// (a spring, a damper, an actuator), with respect to the world position and
// velocity of the other point. `other` on the ground (the default) means F
// depends on no other point. All derivatives 3 x 3, world frame.
struct PointForceTerm {
  BodyPoint point;
  Eigen::Vector3d F_W = Eigen::Vector3d::Zero();
  Eigen::Matrix3d dF_dp = Eigen::Matrix3d::Zero();  // N/m
  Eigen::Matrix3d dF_dv = Eigen::Matrix3d::Zero();  // N s/m
  BodyPoint other;
  Eigen::Matrix3d dF_dp_other = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d dF_dv_other = Eigen::Matrix3d::Zero();
};

// Buffers of dynamics_derivatives, sized once from a Model (N bodies).
struct DynamicsDerivativesWorkspace {
  explicit DynamicsDerivativesWorkspace(const Model& model);

  std::vector<Vector6d> Zdot;     // full Zdot_j at zdd, Eq. (5)
  std::vector<Vector6d> h;        // Mbar_j Zdot_j - Qbar_j (Eqs. 9-10), gravity only
  std::vector<Vector6d> H;        // h summed over each body's subtree (T^T of Eq. 12)
  std::vector<Vector6d> dH;       // H's variation for one coordinate (subtree fill)
  std::vector<Vector6d> dH_rate;  // and for its rate
  // Subtree sums of a body's residual variation per unit b_k, c_k (z) and
  // b_k (zd): see fill_columns_factored in dynamics_derivatives.cpp.
  std::vector<Matrix6d> SA, SC, SD;
  // Their projections on b_i: K(i, k) = row_b . b_k - row_rate_b . u_k + row_c . c_k.
  std::vector<Vector6d> row_b, row_c, row_rate_b;
  std::vector<Eigen::Matrix3d> J;     // world inertia about the COM
  std::vector<Eigen::Vector3d> gdot;  // COM velocity, Eq. (6)
  std::vector<Eigen::Vector3d> Jw;    // J omega
  std::vector<Eigen::Vector3d> Ja;    // J alpha (alpha of the full Zdot)
  // Every body's subtree (itself first, then its descendants in increasing
  // order): subtree_bodies[subtree_start[k] .. subtree_start[k + 1]). The fill
  // visits these alone, O(sum of depths), not every body after k.
  std::vector<int> subtree_start, subtree_bodies;
  Eigen::Matrix<double, 3, Eigen::Dynamic> cols;  // point Jacobian columns (3 x N)
  // M'(z) zdd - Q'(z, zd) (N) with the given point forces: the value whose
  // derivatives are returned, from the same recursion.
  Eigen::VectorXd residual;
  // Whether the fill is factored (deep trees: mean depth above 6) or swept
  // coordinate by coordinate (shallow trees); set from the model, both exact.
  bool use_factored_fill = false;
  // Whether dynamics_derivatives zeroes K and C before filling them (O(N^2)).
  // A caller whose K and C are zero wherever neither coordinate is an ancestor
  // of the other (matrices zeroed once, written by this function alone, with
  // the same point forces every call) may turn it off: the fill then costs
  // O(sum of depths), linear in N for a tree of bounded depth.
  bool zero_unrelated = true;
};

// K = d(M' zdd - Q')/dz and C = d(M' zdd - Q')/dzd (N x N each; row i is the
// equation of coordinate i, column k the coordinate or rate differentiated), for
// M', Q' as mass_matrix_and_forces (Eq. 12) gives them after reset_applied_forces
// and apply_point_force(point.body, position of point, F_W) for every term.
// Valid after forward_kinematics(model, data, z, zd); data's applied loads and
// M, Q are not used. zdd of size N. Throws std::invalid_argument on a size
// mismatch. Does not allocate. Cost O(N) 6 x 6 products, a few dot products per
// ancestor/descendant pair, O(N^2) to zero K and C (unless ws.zero_unrelated
// is off), plus O(depth^2) per force (O(depth^3) with zero_unrelated off).
void dynamics_derivatives(const Model& model, const Data& data, const Eigen::VectorXd& zdd,
                          const std::vector<PointForceTerm>& forces,
                          DynamicsDerivativesWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> K,
                          Eigen::Ref<Eigen::MatrixXd> C);

}  // namespace mh
