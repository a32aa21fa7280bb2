#include "monohydra/core/constraints.hpp"

#include <Eigen/Geometry>

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

void evaluate_constraints(const Model& model, const Data& data, Constraints& cs,
                          Eigen::Ref<Eigen::VectorXd> phi, Eigen::Ref<Eigen::MatrixXd> phi_z,
                          Eigen::Ref<Eigen::VectorXd> phi_dot_zd) {
  for (int i = 0; i < cs.size(); ++i) {
    const ConstraintRow& row = cs.rows[static_cast<size_t>(i)];
    if (row.kind == ConstraintRow::Kind::point) {
      // f = n . r, r = p_b - p_a, n fixed in `frame` (rotating with omega_F):
      // fdot = (n x r) . omega_F + n . (v_b - v_a).
      const Eigen::Matrix3d RF = body_rotation(data, row.frame);
      const Eigen::Vector3d n = RF * row.n;
      const Eigen::Vector3d w = body_angular_velocity(data, row.frame);
      const Eigen::Vector3d r = point_position(data, row.b) - point_position(data, row.a);
      const Eigen::Vector3d rd = point_velocity(data, row.b) - point_velocity(data, row.a);
      const Eigen::Vector3d rdd0 =
          point_bias_acceleration(data, row.b) - point_bias_acceleration(data, row.a);
      const Eigen::Vector3d nd = w.cross(n);
      const Eigen::Vector3d ndd0 = angular_bias(data, row.frame).cross(n) + w.cross(nd);
      phi[i] = n.dot(r);
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
      phi_z.row(i).noalias() = n.transpose() * (cs.J1 - cs.J2) + n.cross(r).transpose() * cs.J3;
      phi_dot_zd[i] = ndd0.dot(r) + 2.0 * nd.dot(rd) + n.dot(rdd0);
    } else {
      // f = c . d with c on body a, d on body b: fdot = (c x d) . (omega_a - omega_b).
      const Eigen::Vector3d c = body_rotation(data, row.a.body) * row.c;
      const Eigen::Vector3d d = body_rotation(data, row.b.body) * row.d;
      const Eigen::Vector3d wa = body_angular_velocity(data, row.a.body);
      const Eigen::Vector3d wb = body_angular_velocity(data, row.b.body);
      const Eigen::Vector3d cd = wa.cross(c), dd = wb.cross(d);
      const Eigen::Vector3d cdd0 = angular_bias(data, row.a.body).cross(c) + wa.cross(cd);
      const Eigen::Vector3d ddd0 = angular_bias(data, row.b.body).cross(d) + wb.cross(dd);
      phi[i] = c.dot(d);
      angular_jacobian_or_zero(model, data, row.a.body, cs.J1);
      angular_jacobian_or_zero(model, data, row.b.body, cs.J2);
      phi_z.row(i).noalias() = c.cross(d).transpose() * (cs.J1 - cs.J2);
      phi_dot_zd[i] = cdd0.dot(d) + 2.0 * cd.dot(dd) + c.dot(ddd0);
    }
  }
}

}  // namespace mh
