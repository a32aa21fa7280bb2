// Analytic derivatives of the loop-closure terms (Sects. 2.2-2.3) for the
// Newton tangents of the closed-loop formulations, without finite differences:
// of the generalized constraint forces Phi_z^T v (Eq. 18, v = alpha Phi + lambda)
// and of the constraint accelerations A = Phi_z zdd + Phi_z_dot zd (Eqs. 15, 21).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/constraints.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

// Buffers of the constraint derivatives, sized once from a Model (N bodies).
struct ConstraintDerivativesWorkspace {
  explicit ConstraintDerivativesWorkspace(const Model& model);

  std::vector<Vector6d> Zdot;                // full Zdot_j at zdd, Eq. (5)
  std::vector<char> mask_x, mask_y, mask_z;  // paths to the ground of a row's bodies
  std::vector<int> coordinates;              // the coordinates a row depends on (N)
};

// d(Phi_z(z)^T v)/dz (N x N, symmetric: sum_i v_i times the Hessian of Phi_i)
// into dPhizTv_dz, for a fixed v of size m = constraints.size(). Valid after
// forward_kinematics (only the positions are used). Throws
// std::invalid_argument on a size mismatch. Does not allocate. Cost O(m (N + depth^2)).
void constraint_force_derivative(const Model& model, const Data& data,
                                 const Constraints& constraints, const Eigen::VectorXd& v,
                                 ConstraintDerivativesWorkspace& ws,
                                 Eigen::Ref<Eigen::MatrixXd> dPhizTv_dz);

// dA/dz and dA/dzd (m x N each) of the constraint accelerations
// A(z, zd, zdd) = Phi_z zdd + Phi_z_dot zd (phi_z and phi_dot_zd as
// evaluate_constraints gives them; A is the second time derivative of Phi),
// at the kinematics in data (after forward_kinematics(model, data, z, zd)) and
// zdd of size N. Throws std::invalid_argument on a size mismatch. Does not
// allocate. Cost O(m N).
void constraint_acceleration_derivatives(const Model& model, const Data& data,
                                         const Constraints& constraints, const Eigen::VectorXd& zdd,
                                         ConstraintDerivativesWorkspace& ws,
                                         Eigen::Ref<Eigen::MatrixXd> dA_dz,
                                         Eigen::Ref<Eigen::MatrixXd> dA_dzd);

}  // namespace mh
