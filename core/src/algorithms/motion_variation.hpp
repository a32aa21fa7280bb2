// How the semirecursive kinematics (Sect. 2.1, Eqs. 1-7) of one body change
// when one joint coordinate z_k or rate zd_k changes: shared by the derivatives
// of the dynamics and of the constraints so that both differentiate the tree
// the same way. Private to the core.
//
// Z_j = [sdot_j; omega_j] (Eq. 1) is a twist in world coordinates, so the tree
// algebra is that of twists. With the bracket (motion cross product)
//   [v1; w1] x [v2; w2] = [w1 x v2 + v1 x w2; w1 x w2]
// the vectors of Eqs. (2)-(3) satisfy bdot_j = Z_parent x b_j and
// d_j = Z_parent x b_j zd_j. A change dz_k moves the subtree of k rigidly with the
// twist b_k dz_k: every b_i below k (not b_k) turns into b_i + (b_k x b_i) dz_k,
// and every point p and vector x fixed on the subtree moves by (b_k at p) dz_k and
// (omega(b_k) x x) dz_k. Summing Eq. (2)/(3) along the path from k to a body e
// below it then gives, with Y = Z_e - Z_k (Jacobi identity for the bracket),
//   dZ_e/dz_k   = b_k x Y
//   dZdd_e/dz_k = b_k x ((Zdd_e - Zdd_k) - Z_k x Y) + Z_k x (b_k x Y)
//   dZ_e/dzd_k  = b_k
//   dZdd_e/dzd_k = Z_k x b_k + b_k x Y = b_k x (Z_e - 2 Z_k)
// where Zdd_e is the full Zdot_e of Eq. (5) (or Zdot0_e when zdd = 0: the zdd
// part only adds b_k x (sum of b_i zdd_i) to the first, which is already in it).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"

namespace mh::detail {

// The motion cross product of twists in the [linear; angular] order of Eq. (1).
inline Vector6d motion_cross(const Vector6d& a, const Vector6d& b) {
  Vector6d out;
  out.head<3>() = a.tail<3>().cross(b.head<3>()) + a.head<3>().cross(b.tail<3>());
  out.tail<3>() = a.tail<3>().cross(b.tail<3>());
  return out;
}

// Velocity at world point p of the twist t.
inline Eigen::Vector3d twist_at(const Vector6d& t, const Eigen::Vector3d& p) {
  return t.head<3>() + t.tail<3>().cross(p);
}

// The change of one body's kinematic state per unit change of one coordinate or rate:
// the rigid displacement twist of its geometry, and the changes of Z and of Zdot.
struct BodyVariation {
  Vector6d twist = Vector6d::Zero();  // geometry: points move by twist_at(twist, p)
  Vector6d Z = Vector6d::Zero();      // dZ_e
  Vector6d Zdot = Vector6d::Zero();   // dZdot_e (full, Eq. 5)
};

// d/dz_k of body e's state, k an ancestor of e or e itself. Zdot: the full Zdot
// of every body (Eq. 5, zdd included).
inline BodyVariation variation_z(const Data& data, const std::vector<Vector6d>& Zdot, int e,
                                 int k) {
  BodyVariation v;
  const Vector6d& bk = data.b[k];
  const Vector6d& Zk = data.Z[k];
  const Vector6d Y = data.Z[e] - Zk;
  v.twist = bk;
  v.Z = motion_cross(bk, Y);
  v.Zdot =
      motion_cross(bk, Vector6d(Zdot[e] - Zdot[k] - motion_cross(Zk, Y))) + motion_cross(Zk, v.Z);
  return v;
}

// d/dzd_k of body e's state, k an ancestor of e or e itself.
inline BodyVariation variation_zd(const Data& data, int e, int k) {
  BodyVariation v;
  const Vector6d& bk = data.b[k];
  v.Z = bk;
  v.Zdot = motion_cross(bk, Vector6d(data.Z[e] - 2.0 * data.Z[k]));
  return v;
}

// Position, velocity and acceleration of a point fixed on a body (Eqs. 6-7 for
// the centre of mass; see point_bias_acceleration for the omega x v term).
struct PointMotion {
  Eigen::Vector3d p, v, a;
};

inline PointMotion point_motion(const Eigen::Vector3d& p, const Vector6d& Z, const Vector6d& Zdot) {
  PointMotion m;
  m.p = p;
  m.v = twist_at(Z, p);
  m.a = twist_at(Zdot, p) + Z.tail<3>().cross(m.v);
  return m;
}

inline PointMotion vary_point(const PointMotion& m, const Vector6d& Z, const Vector6d& Zdot,
                              const BodyVariation& dv) {
  const Eigen::Vector3d w = Z.tail<3>();
  PointMotion d;
  d.p = twist_at(dv.twist, m.p);
  d.v = twist_at(dv.Z, m.p) + w.cross(d.p);
  d.a =
      twist_at(dv.Zdot, m.p) + Zdot.tail<3>().cross(d.p) + dv.Z.tail<3>().cross(m.v) + w.cross(d.v);
  return d;
}

// A vector x fixed on a body, and its first and second time derivatives.
inline PointMotion vector_motion(const Eigen::Vector3d& x, const Vector6d& Z,
                                 const Vector6d& Zdot) {
  const Eigen::Vector3d w = Z.tail<3>();
  PointMotion m;
  m.p = x;
  m.v = w.cross(x);
  m.a = Zdot.tail<3>().cross(x) + w.cross(m.v);
  return m;
}

inline PointMotion vary_vector(const PointMotion& m, const Vector6d& Z, const Vector6d& Zdot,
                               const BodyVariation& dv) {
  const Eigen::Vector3d w = Z.tail<3>();
  const Eigen::Vector3d dw = dv.Z.tail<3>();
  PointMotion d;
  d.p = dv.twist.tail<3>().cross(m.p);
  d.v = dw.cross(m.p) + w.cross(d.p);
  d.a = dv.Zdot.tail<3>().cross(m.p) + Zdot.tail<3>().cross(d.p) + dw.cross(m.v) + w.cross(d.v);
  return d;
}

// Marks the path from `body` to the ground: mask[k] = 1 for k an ancestor of body
// or body itself, else 0. mask has one entry per body.
inline void mark_path(const Model& model, int body, std::vector<char>& mask) {
  std::fill(mask.begin(), mask.end(), 0);
  for (int k = body; k != kGround; k = model.bodies[k].parent) mask[k] = 1;
}

}  // namespace mh::detail
