#include "monohydra/core/constraints.hpp"

#include <Eigen/Geometry>

#include "algorithms/motion_variation.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {
namespace {

// Two unit vectors completing `axis` to an orthonormal triad.
void perpendiculars(const Eigen::Vector3d& axis, Eigen::Vector3d& n1, Eigen::Vector3d& n2) {
  const Eigen::Vector3d ref =
      std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  n1 = axis.cross(ref).normalized();
  n2 = axis.cross(n1);
}

ConstraintRow point_row(int joint, const CutJoint& cj, int frame, const Eigen::Vector3d& n) {
  ConstraintRow r;
  r.kind = ConstraintRow::Kind::point;
  r.joint = joint;
  r.a = cj.a;
  r.b = cj.b;
  r.frame = frame;
  r.n = n;
  return r;
}

ConstraintRow dot_row(int joint, const CutJoint& cj, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& d) {
  ConstraintRow r;
  r.kind = ConstraintRow::Kind::dot;
  r.joint = joint;
  r.a = cj.a;
  r.b = cj.b;
  r.c = c;
  r.d = d;
  return r;
}

// Bias (zdd = 0) angular acceleration of a body; zero for the ground.
Eigen::Vector3d angular_bias(const Data& data, int body) {
  return body == kGround ? Eigen::Vector3d::Zero() : Eigen::Vector3d(data.Zdot0[body].tail<3>());
}

// A point's position, velocity and velocity-product (zdd = 0) acceleration
// from one position (motion_variation.hpp's, as the constraint derivatives
// compute them; the ground's point stands).
detail::PointMotion point_motion(const Data& data, const BodyPoint& point) {
  if (point.body == kGround)
    return detail::point_motion(point.p_B, Vector6d::Zero(), Vector6d::Zero());
  return detail::point_motion(point_position(data, point), data.Z[point.body],
                              data.Zdot0[point.body]);
}

void angular_jacobian_or_zero(const Model& model, const Data& data, int body,
                              Eigen::Matrix<double, 3, Eigen::Dynamic>& J) {
  if (body == kGround)
    J.setZero();
  else
    angular_jacobian(model, data, body, J);
}

}  // namespace

Constraints build_constraints(const Model& model, const Data& data) {
  Constraints out;
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  for (int j = 0; j < static_cast<int>(model.cut_joints.size()); ++j) {
    const CutJoint& cj = model.cut_joints[static_cast<size_t>(j)];
    Eigen::Vector3d a1, a2, b1, b2;
    perpendiculars(cj.axis_a, a1, a2);
    perpendiculars(cj.axis_b, b1, b2);
    const int world_rows = model.planar ? 2 : 3;
    switch (cj.type) {
      case CutJointType::revolute:
      case CutJointType::spherical:
        for (int k = 0; k < world_rows; ++k)
          out.rows.push_back(point_row(j, cj, kGround, Eigen::Vector3d::Unit(k)));
        if (cj.type == CutJointType::revolute && !model.planar) {
          out.rows.push_back(dot_row(j, cj, cj.axis_a, b1));  // axes stay parallel
          out.rows.push_back(dot_row(j, cj, cj.axis_a, b2));
        }
        break;
      case CutJointType::translational:
        if (model.planar) {
          // Point b on the line through a along the axis; no relative rotation.
          out.rows.push_back(point_row(j, cj, cj.a.body, ez.cross(cj.axis_a)));
          out.rows.push_back(dot_row(j, cj, cj.axis_a, ez.cross(cj.axis_b)));
        } else {
          out.rows.push_back(point_row(j, cj, cj.a.body, a1));
          out.rows.push_back(point_row(j, cj, cj.a.body, a2));
          out.rows.push_back(dot_row(j, cj, cj.axis_a, b1));
          out.rows.push_back(dot_row(j, cj, cj.axis_a, b2));
          // Twist about the axis, locked as it is at the initial coordinates.
          const Eigen::Matrix3d Ra = body_rotation(data, cj.a.body);
          const Eigen::Matrix3d Rb = body_rotation(data, cj.b.body);
          out.rows.push_back(dot_row(j, cj, a1, Rb.transpose() * (Ra * a2)));
        }
        break;
    }
  }
  const int N = model.num_coordinates();
  out.J1.setZero(3, N);
  out.J2.setZero(3, N);
  out.J3.setZero(3, N);
  return out;
}

void evaluate_constraint_positions(const Model& model, const Data& data, Constraints& cs,
                                   Eigen::Ref<Eigen::VectorXd> phi,
                                   Eigen::Ref<Eigen::MatrixXd> phi_z) {
  // Rows of one joint follow each other and share their bodies: their point
  // or angular Jacobians are built once per joint and row kind, not per row.
  int built_joint = -1;
  ConstraintRow::Kind built_kind = ConstraintRow::Kind::point;
  int built_frame = kGround;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int i = 0; i < cs.size(); ++i) {
    const ConstraintRow& row = cs.rows[static_cast<size_t>(i)];
    const bool built = row.joint == built_joint && row.kind == built_kind &&
                       (row.kind == ConstraintRow::Kind::dot || row.frame == built_frame);
    if (row.kind == ConstraintRow::Kind::point) {
      // f = n . r, r = p_b - p_a, n fixed in `frame`.
      const Eigen::Vector3d n = body_rotation(data, row.frame) * row.n;
      if (!built) {
        r = point_position(data, row.b) - point_position(data, row.a);
        // Jacobian rows from the point Jacobians (velocity = J zd).
        if (row.b.body == kGround)
          cs.J1.setZero();
        else
          point_jacobian(model, data, row.b, cs.J1);
        if (row.a.body == kGround)
          cs.J2.setZero();
        else
          point_jacobian(model, data, row.a, cs.J2);
        angular_jacobian_or_zero(model, data, row.frame, cs.J3);
      }
      phi[i] = n.dot(r);
      phi_z.row(i).noalias() =
          n.transpose().lazyProduct(cs.J1 - cs.J2) + n.cross(r).transpose().lazyProduct(cs.J3);
    } else {
      // f = c . d with c on body a, d on body b.
      const Eigen::Vector3d c = body_rotation(data, row.a.body) * row.c;
      const Eigen::Vector3d d = body_rotation(data, row.b.body) * row.d;
      phi[i] = c.dot(d);
      if (!built) {
        angular_jacobian_or_zero(model, data, row.a.body, cs.J1);
        angular_jacobian_or_zero(model, data, row.b.body, cs.J2);
      }
      phi_z.row(i).noalias() = c.cross(d).transpose().lazyProduct(cs.J1 - cs.J2);
    }
    built_joint = row.joint;
    built_kind = row.kind;
    built_frame = row.frame;
  }
}

void evaluate_constraint_velocity_terms(const Data& data, const Constraints& cs,
                                        Eigen::Ref<Eigen::VectorXd> phi_dot_zd) {
  // As for the positions, rows of one joint share r, its rates and the
  // frame's motion: each point's position, velocity and velocity-product
  // acceleration is computed once per joint (as point_velocity and
  // point_bias_acceleration compute them) rather than once per call.
  int built_joint = -1;
  int built_frame = kGround;
  Eigen::Vector3d r = Eigen::Vector3d::Zero(), rd = r, rdd0 = r, w = r, alpha0 = r;
  for (int i = 0; i < cs.size(); ++i) {
    const ConstraintRow& row = cs.rows[static_cast<size_t>(i)];
    if (row.kind == ConstraintRow::Kind::point) {
      // f = n . r, n fixed in `frame` (rotating with omega_F):
      // fdot = (n x r) . omega_F + n . (v_b - v_a).
      if (row.joint != built_joint || row.frame != built_frame) {
        const detail::PointMotion b = point_motion(data, row.b);
        const detail::PointMotion a = point_motion(data, row.a);
        r = b.p - a.p;
        rd = b.v - a.v;
        rdd0 = b.a - a.a;
        w = body_angular_velocity(data, row.frame);
        alpha0 = angular_bias(data, row.frame);
        built_joint = row.joint;
        built_frame = row.frame;
      }
      const Eigen::Vector3d n = body_rotation(data, row.frame) * row.n;
      const Eigen::Vector3d nd = w.cross(n);
      const Eigen::Vector3d ndd0 = alpha0.cross(n) + w.cross(nd);
      phi_dot_zd[i] = ndd0.dot(r) + 2.0 * nd.dot(rd) + n.dot(rdd0);
    } else {
      // f = c . d: fdot = (c x d) . (omega_a - omega_b).
      const Eigen::Vector3d c = body_rotation(data, row.a.body) * row.c;
      const Eigen::Vector3d d = body_rotation(data, row.b.body) * row.d;
      const Eigen::Vector3d wa = body_angular_velocity(data, row.a.body);
      const Eigen::Vector3d wb = body_angular_velocity(data, row.b.body);
      const Eigen::Vector3d cd = wa.cross(c), dd = wb.cross(d);
      const Eigen::Vector3d cdd0 = angular_bias(data, row.a.body).cross(c) + wa.cross(cd);
      const Eigen::Vector3d ddd0 = angular_bias(data, row.b.body).cross(d) + wb.cross(dd);
      phi_dot_zd[i] = cdd0.dot(d) + 2.0 * cd.dot(dd) + c.dot(ddd0);
      built_joint = -1;
    }
  }
}

// The writable views are handed on as views (Eigen's way for output
// arguments: a Ref by value is a pointer and sizes), which clang-tidy reads as
// a copy of a value only read.
// NOLINTBEGIN(performance-unnecessary-value-param)
void evaluate_constraints(const Model& model, const Data& data, Constraints& cs,
                          Eigen::Ref<Eigen::VectorXd> phi, Eigen::Ref<Eigen::MatrixXd> phi_z,
                          Eigen::Ref<Eigen::VectorXd> phi_dot_zd) {
  evaluate_constraint_positions(model, data, cs, phi, phi_z);
  evaluate_constraint_velocity_terms(data, cs, phi_dot_zd);
}
// NOLINTEND(performance-unnecessary-value-param)

}  // namespace mh
