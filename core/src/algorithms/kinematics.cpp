// Open-loop semirecursive kinematics (Sect. 2.1, Eqs. 1-7).
//
// Convention: Z_j = [sdot_j; omega_j] where sdot_j is the velocity of the body
// point that is momentarily at the world origin, and Zdot_j is the plain time
// derivative of Z_j (Eq. 5: Zdot = T R_d zdd + T Rdot_d zd), so d_j = bdot_j zd_j.
// Because sdot_j is a velocity *field value at a fixed place* rather than the
// velocity of one material point, d(sdot_j)/dt is not the acceleration of the
// body point at the origin: that one is d(sdot_j)/dt + omega_j x sdot_j. Point
// accelerations below carry that extra term (see point_bias_acceleration).
#include "monohydra/core/kinematics.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace mh {
namespace {

[[noreturn]] void throw_size(const char* where, const char* what, Eigen::Index expected,
                             Eigen::Index got) {
  throw std::invalid_argument(std::string(where) + ": " + what + ": expected " +
                              std::to_string(expected) + ", got " + std::to_string(got));
}

[[noreturn]] __attribute__((noinline, cold)) void throw_bad_body(const char* where, int n,
                                                                 int body) {
  throw std::invalid_argument(std::string(where) + ": body: expected " + std::to_string(kGround) +
                              ".." + std::to_string(n - 1) + ", got " + std::to_string(body));
}

// The check stays (a bad index is a clear error, not a crash) but costs one
// inlined comparison on the hot path: the message is built out of line.
inline void check_body(const char* where, const Data& data, int body) {
  const int n = static_cast<int>(data.R_W_B.size());
  if (__builtin_expect(body < kGround || body >= n, 0)) throw_bad_body(where, n, body);
}

void check_data(const char* where, const Model& model, const Data& data) {
  if (static_cast<int>(data.R_W_B.size()) != model.num_bodies() ||
      data.M.rows() != model.num_coordinates()) {
    throw_size(where, "data (bodies)", model.num_bodies(),
               static_cast<Eigen::Index>(data.R_W_B.size()));
  }
}

}  // namespace

void forward_kinematics(const Model& model, Data& data, const Eigen::VectorXd& z,
                        const Eigen::VectorXd& zd) {
  const int n = model.num_bodies();
  if (z.size() != model.num_coordinates()) {
    throw_size("forward_kinematics", "z", model.num_coordinates(), z.size());
  }
  if (zd.size() != model.num_coordinates()) {
    throw_size("forward_kinematics", "zd", model.num_coordinates(), zd.size());
  }
  check_data("forward_kinematics", model, data);

  data.z = z;  // same size: a copy into the existing buffer, no allocation
  data.zd = zd;

  for (int j = 0; j < n; ++j) {
    const Body& body = model.bodies[j];
    const int p = body.parent;
    if (p < kGround || p >= j) {  // parents precede children (model.hpp)
      throw std::invalid_argument("forward_kinematics: bodies[" + std::to_string(j) +
                                  "].parent: expected " + std::to_string(kGround) + ".." +
                                  std::to_string(j - 1) + ", got " + std::to_string(p));
    }
    // Parent frame, velocity and velocity-product acceleration (ground: at rest).
    const Eigen::Matrix3d R_P = p == kGround ? Eigen::Matrix3d::Identity() : data.R_W_B[p];
    const Eigen::Vector3d o_P = p == kGround ? Eigen::Vector3d::Zero() : data.o_W[p];
    const Vector6d Z_P = p == kGround ? Vector6d::Zero() : data.Z[p];
    const Vector6d Zdot0_P = p == kGround ? Vector6d::Zero() : data.Zdot0[p];
    const Eigen::Vector3d sdot_P = Z_P.head<3>();
    const Eigen::Vector3d omega_P = Z_P.tail<3>();

    const Eigen::Vector3d u = R_P * body.axis_P;
    // The axis is fixed on the parent, so it turns with the parent.
    const Eigen::Vector3d udot = omega_P.cross(u);
    Vector6d b;
    Vector6d bdot;
    if (body.joint == JointType::revolute) {
      const Eigen::Vector3d o = o_P + R_P * body.joint_P;
      data.R_W_B[j] = R_P * Eigen::AngleAxisd(z[j], body.axis_P).toRotationMatrix() * body.R_P_B0;
      data.o_W[j] = o;
      // Eq. (2), revolute: a unit rotation about the axis through o moves the
      // point at the world origin with velocity u x (0 - o) = o x u.
      b << o.cross(u), u;
      // The joint point o is fixed on the parent: odot is the parent's velocity there.
      const Eigen::Vector3d odot = sdot_P + omega_P.cross(o);
      bdot << odot.cross(u) + o.cross(udot), udot;
    } else {
      data.R_W_B[j] = R_P * body.R_P_B0;
      data.o_W[j] = o_P + R_P * (body.joint_P + body.axis_P * z[j]);
      // Eq. (2), prismatic: pure translation along u.
      b << u, Eigen::Vector3d::Zero();
      bdot << udot, Eigen::Vector3d::Zero();
    }
    data.u_W[j] = u;
    data.g_W[j] = data.o_W[j] + data.R_W_B[j] * body.com_B;
    data.b[j] = b;
    data.Z[j] = Z_P + b * zd[j];          // Eq. (2)
    data.d[j] = bdot * zd[j];             // Eq. (3): d_j = bdot_j zd_j
    data.Zdot0[j] = Zdot0_P + data.d[j];  // Eq. (3) with zdd = 0, i.e. T Rdot_d zd of Eq. (5)
  }
}

void forward_velocities(const Model& model, Data& data, const Eigen::VectorXd& zd) {
  const int n = model.num_bodies();
  if (zd.size() != model.num_coordinates()) {
    throw_size("forward_velocities", "zd", model.num_coordinates(), zd.size());
  }
  check_data("forward_velocities", model, data);
  data.zd = zd;
  for (int j = 0; j < n; ++j) {
    const Body& body = model.bodies[j];
    const int p = body.parent;
    if (p < kGround || p >= j) {  // parents precede children (model.hpp)
      throw std::invalid_argument("forward_velocities: bodies[" + std::to_string(j) +
                                  "].parent: expected " + std::to_string(kGround) + ".." +
                                  std::to_string(j - 1) + ", got " + std::to_string(p));
    }
    // As forward_kinematics, with u, o and b as it left them.
    const Vector6d Z_P = p == kGround ? Vector6d::Zero() : data.Z[p];
    const Vector6d Zdot0_P = p == kGround ? Vector6d::Zero() : data.Zdot0[p];
    const Eigen::Vector3d sdot_P = Z_P.head<3>();
    const Eigen::Vector3d omega_P = Z_P.tail<3>();
    const Eigen::Vector3d& u = data.u_W[j];
    const Eigen::Vector3d udot = omega_P.cross(u);
    Vector6d bdot;
    if (body.joint == JointType::revolute) {
      const Eigen::Vector3d& o = data.o_W[j];
      const Eigen::Vector3d odot = sdot_P + omega_P.cross(o);
      bdot << odot.cross(u) + o.cross(udot), udot;
    } else {
      bdot << udot, Eigen::Vector3d::Zero();
    }
    data.Z[j] = Z_P + data.b[j] * zd[j];  // Eq. (2)
    data.d[j] = bdot * zd[j];             // Eq. (3)
    data.Zdot0[j] = Zdot0_P + data.d[j];  // Eq. (3) with zdd = 0
  }
}

Eigen::Vector3d point_position(const Data& data, const BodyPoint& point) {
  check_body("point_position", data, point.body);
  if (point.body == kGround) return point.p_B;
  return data.o_W[point.body] + data.R_W_B[point.body] * point.p_B;
}

Eigen::Vector3d point_velocity(const Data& data, const BodyPoint& point) {
  check_body("point_velocity", data, point.body);
  if (point.body == kGround) return Eigen::Vector3d::Zero();
  const Vector6d& Z = data.Z[point.body];
  const Eigen::Vector3d p = point_position(data, point);
  return Z.head<3>() + Z.tail<3>().cross(p);
}

Eigen::Vector3d point_bias_acceleration(const Data& data, const BodyPoint& point) {
  check_body("point_bias_acceleration", data, point.body);
  if (point.body == kGround) return Eigen::Vector3d::Zero();
  const Vector6d& Z = data.Z[point.body];
  const Vector6d& Zdot0 = data.Zdot0[point.body];
  const Eigen::Vector3d p = point_position(data, point);
  const Eigen::Vector3d omega = Z.tail<3>();
  const Eigen::Vector3d v = Z.head<3>() + omega.cross(p);
  // d/dt (sdot + omega x p) with pdot = v. Since Zdot is the plain derivative of
  // Z, the velocity-product term is omega x v = omega x sdot + omega x (omega x p),
  // not only the centripetal omega x (omega x p) of Eq. (7) (see the file comment).
  return Zdot0.head<3>() + Zdot0.tail<3>().cross(p) + omega.cross(v);
}

Eigen::Vector3d body_angular_velocity(const Data& data, int body) {
  check_body("body_angular_velocity", data, body);
  if (body == kGround) return Eigen::Vector3d::Zero();
  return data.Z[body].tail<3>();
}

Eigen::Matrix3d body_rotation(const Data& data, int body) {
  check_body("body_rotation", data, body);
  if (body == kGround) return Eigen::Matrix3d::Identity();
  return data.R_W_B[body];
}

void point_jacobian(const Model& model, const Data& data, const BodyPoint& point,
                    Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> J) {
  check_body("point_jacobian", data, point.body);
  if (J.cols() != model.num_coordinates()) {
    throw_size("point_jacobian", "J columns", model.num_coordinates(), J.cols());
  }
  J.setZero();
  if (point.body == kGround) return;
  const Eigen::Vector3d p = point_position(data, point);
  // Column k: velocity of the point for Z = b_k (Eq. 4), nonzero on the path to the root.
  for (int k = point.body; k != kGround; k = model.bodies[k].parent) {
    J.col(k) = data.b[k].head<3>() + data.b[k].tail<3>().cross(p);
  }
}

void angular_jacobian(const Model& model, const Data& data, int body,
                      Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> J) {
  check_body("angular_jacobian", data, body);
  if (J.cols() != model.num_coordinates()) {
    throw_size("angular_jacobian", "J columns", model.num_coordinates(), J.cols());
  }
  J.setZero();
  for (int k = body; k != kGround; k = model.bodies[k].parent) J.col(k) = data.b[k].tail<3>();
}

bool is_ancestor_or_self(const Model& model, int ancestor, int body) {
  const int n = model.num_bodies();
  if (ancestor < kGround || ancestor >= n || body < kGround || body >= n) {
    throw std::invalid_argument("is_ancestor_or_self: bodies: expected " + std::to_string(kGround) +
                                ".." + std::to_string(n - 1) + ", got " + std::to_string(ancestor) +
                                " and " + std::to_string(body));
  }
  // The ground is on every path; a walk up from `body` ends at the ground.
  if (ancestor == kGround) return true;
  for (int k = body; k != kGround; k = model.bodies[k].parent) {
    if (k == ancestor) return true;
    if (k < ancestor) return false;  // parents precede children: cannot reach it any more
  }
  return false;
}

}  // namespace mh
