// Loop-closure constraints Phi(z) = 0 of the cut joints (Sect. 2.2), their
// Jacobian Phi_z and the velocity-product term Phi_z_dot zd, from the
// semirecursive kinematics. Every row is one of two kinds:
//   point row: n . (p_b - p_a)   with n fixed in a frame (a body, or the world)
//   dot row:   c . d             with c fixed in body a and d fixed in body b
// so one differentiation serves every joint type.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh {

struct ConstraintRow {
  enum class Kind { point, dot };
  Kind kind = Kind::point;
  int joint = 0;        // index into Model::cut_joints
  BodyPoint a, b;       // point rows: the two points; dot rows: their bodies
  int frame = kGround;  // point rows: the frame n is fixed in
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  // point rows
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // dot rows, body a's frame
  Eigen::Vector3d d = Eigen::Vector3d::Zero();  // dot rows, body b's frame
};

// The constraint rows of a model and the buffers to evaluate them. Built once.
struct Constraints {
  std::vector<ConstraintRow> rows;
  // Workspaces (3 x N), so evaluation does not allocate.
  Eigen::Matrix<double, 3, Eigen::Dynamic> J1, J2, J3;
  int size() const { return static_cast<int>(rows.size()); }
};

// Rows per cut joint: revolute 3 (coincident points) + 2 (axes aligned),
// spherical 3, translational 2 (point on the sliding line) + 3 (no relative
// rotation); in a planar model revolute and spherical 2, translational 2 (one
// offset, one angle). `data` holds the kinematics at the initial coordinates:
// the translational joint's twist is locked as it is there.
Constraints build_constraints(const Model& model, const Data& data);

// Phi (m), Phi_z (m x N) and Phi_z_dot zd (m) at the kinematics in `data`
// (after forward_kinematics). Does not allocate. The two halves below, apart:
// Phi and Phi_z depend on z alone, so a caller that changes only zd (the
// rates of a converged z) needs only the velocity terms again.
void evaluate_constraints(const Model& model, const Data& data, Constraints& constraints,
                          Eigen::Ref<Eigen::VectorXd> phi, Eigen::Ref<Eigen::MatrixXd> phi_z,
                          Eigen::Ref<Eigen::VectorXd> phi_dot_zd);

// Phi and Phi_z only (positions).
void evaluate_constraint_positions(const Model& model, const Data& data, Constraints& constraints,
                                   Eigen::Ref<Eigen::VectorXd> phi,
                                   Eigen::Ref<Eigen::MatrixXd> phi_z);

// Phi_z_dot zd only (velocities and the velocity-product accelerations in `data`).
void evaluate_constraint_velocity_terms(const Data& data, const Constraints& constraints,
                                        Eigen::Ref<Eigen::VectorXd> phi_dot_zd);

}  // namespace mh
