// Tests of the open-loop semirecursive dynamics (Sect. 2.1, Eqs. 8-12) against
// an independent absolute-coordinate computation and closed-form cases.
//
// The reference never touches Data's Z, b, d, Zdot0 or Mbar: it composes 4x4
// homogeneous transforms directly from z, differentiates them by complex step
// (exact to rounding: no subtractive cancellation) for the Jacobians, and by a
// fourth-order central difference in time for the velocity-product accelerations.
#include "monohydra/core/dynamics.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using Cplx = std::complex<double>;
using Matrix3Xd = Eigen::Matrix<double, 3, Eigen::Dynamic>;
template <class S>
using Mat4 = Eigen::Matrix<S, 4, 4>;
template <class S>
using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------- random trees

using test::random_tree;
using test::random_vector;
using test::Rng;
using test::scientific;

// ------------------------------------------------- independent reference model

template <class S>
Mat3<S> skew(const Vec3<S>& v) {
  Mat3<S> K;
  K << S(0.0), -v.z(), v.y(), v.z(), S(0.0), -v.x(), -v.y(), v.x(), S(0.0);
  return K;
}

template <class S>
Mat4<S> translation(const Vec3<S>& t) {
  Mat4<S> T = Mat4<S>::Identity();
  T.template topRightCorner<3, 1>() = t;
  return T;
}

template <class S>
Mat4<S> rotation(const Mat3<S>& R) {
  Mat4<S> T = Mat4<S>::Identity();
  T.template topLeftCorner<3, 3>() = R;
  return T;
}

// Rodrigues' formula, written out so it works for complex angles.
template <class S>
Mat3<S> axis_angle(const Eigen::Vector3d& axis, const S& q) {
  using std::cos;
  using std::sin;
  const Mat3<S> K = skew<S>(axis.cast<S>());
  return Mat3<S>::Identity() + sin(q) * K + (S(1.0) - cos(q)) * K * K;
}

// World pose of every body frame by composing the joint transforms of the
// Model's frame convention (model.hpp), parent first.
template <class S>
std::vector<Mat4<S>> body_transforms(const Model& model, const VecX<S>& z) {
  std::vector<Mat4<S>> T(model.bodies.size());
  for (int j = 0; j < model.num_bodies(); ++j) {
    const Body& body = model.bodies[j];
    const Mat4<S> T_P = body.parent == kGround ? Mat4<S>::Identity() : T[body.parent];
    const Mat4<S> B0 = rotation<S>(body.R_P_B0.cast<S>());
    if (body.joint == JointType::revolute) {
      T[j] = T_P * translation<S>(body.joint_P.cast<S>()) *
             rotation<S>(axis_angle<S>(body.axis_P, z[j])) * B0;
    } else {
      const Vec3<S> offset = body.joint_P.cast<S>() + body.axis_P.cast<S>() * z[j];
      T[j] = T_P * translation<S>(offset) * B0;
    }
  }
  return T;
}

// Poses at z and their directional derivatives along v, by complex step.
struct Poses {
  std::vector<Eigen::Matrix4d> T;
  std::vector<Eigen::Matrix4d> Tdot;
};

Poses poses(const Model& model, const Eigen::VectorXd& z, const Eigen::VectorXd& v) {
  constexpr double h = 1e-20;
  const VecX<Cplx> zc = z.cast<Cplx>() + Cplx(0.0, h) * v.cast<Cplx>();
  const std::vector<Mat4<Cplx>> Tc = body_transforms<Cplx>(model, zc);
  Poses out;
  for (const Mat4<Cplx>& T : Tc) {
    out.T.push_back(T.real());
    out.Tdot.push_back(T.imag() / h);
  }
  return out;
}

Eigen::Vector3d transform_point(const Eigen::Matrix4d& T, const Eigen::Vector3d& p) {
  return T.topLeftCorner<3, 3>() * p + T.topRightCorner<3, 1>();
}

Eigen::Vector3d rate_of_point(const Eigen::Matrix4d& Tdot, const Eigen::Vector3d& p) {
  return Tdot.topLeftCorner<3, 3>() * p + Tdot.topRightCorner<3, 1>();
}

// omega from Rdot = omega~ R.
Eigen::Vector3d angular_rate(const Eigen::Matrix4d& T, const Eigen::Matrix4d& Tdot) {
  const Eigen::Matrix3d W = Tdot.topLeftCorner<3, 3>() * T.topLeftCorner<3, 3>().transpose();
  return 0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
}

// f'(0) by the fourth-order central stencil.
template <class F>
auto derivative(F f, double h) {
  return ((f(-2.0 * h) - 8.0 * f(-h) + 8.0 * f(h) - f(2.0 * h)) / (12.0 * h)).eval();
}
constexpr double kTimeStep = 1e-3;

struct Jacobians {
  std::vector<Matrix3Xd> v;  // COM velocity per zd, one 3 x N per body
  std::vector<Matrix3Xd> w;  // angular velocity per zd
};

Jacobians com_jacobians(const Model& model, const Eigen::VectorXd& z) {
  const int n = model.num_coordinates();
  Jacobians J{std::vector<Matrix3Xd>(n, Matrix3Xd::Zero(3, n)),
              std::vector<Matrix3Xd>(n, Matrix3Xd::Zero(3, n))};
  for (int k = 0; k < n; ++k) {
    const Poses P = poses(model, z, Eigen::VectorXd::Unit(n, k));
    for (int j = 0; j < n; ++j) {
      J.v[j].col(k) = rate_of_point(P.Tdot[j], model.bodies[j].com_B);
      J.w[j].col(k) = angular_rate(P.T[j], P.Tdot[j]);
    }
  }
  return J;
}

Eigen::MatrixXd reference_mass_matrix(const Model& model, const Eigen::VectorXd& z) {
  const int n = model.num_coordinates();
  const Jacobians J = com_jacobians(model, z);
  const std::vector<Mat4<double>> T = body_transforms<double>(model, z);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix3d R = T[j].topLeftCorner<3, 3>();
    const Eigen::Matrix3d Jw = R * model.bodies[j].inertia_B * R.transpose();
    M += model.bodies[j].mass * J.v[j].transpose() * J.v[j] + J.w[j].transpose() * Jw * J.w[j];
  }
  return M;
}

// An external force F applied at a body point, on top of gravity.
struct PointLoad {
  BodyPoint point;
  Eigen::Vector3d F = Eigen::Vector3d::Zero();
};

// Generalized applied force: sum Jv_j^T m_j gravity + Jp^T F.
Eigen::VectorXd reference_applied_force(const Model& model, const Eigen::VectorXd& z,
                                        const PointLoad& load) {
  const int n = model.num_coordinates();
  const Jacobians J = com_jacobians(model, z);
  Eigen::VectorXd Q = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n; ++j) Q += J.v[j].transpose() * (model.bodies[j].mass * model.gravity);
  if (load.point.body != kGround) {
    for (int k = 0; k < n; ++k) {
      const Poses P = poses(model, z, Eigen::VectorXd::Unit(n, k));
      Q[k] += rate_of_point(P.Tdot[load.point.body], load.point.p_B).dot(load.F);
    }
  }
  return Q;
}

// Newton-Euler in absolute coordinates projected with the Jacobians (Kane):
// Q' = sum Jv^T (f - m a_bias) + Jw^T (tau - J alpha_bias - omega x J omega).
Eigen::VectorXd reference_forces_newton_euler(const Model& model, const Eigen::VectorXd& z,
                                              const Eigen::VectorXd& zd, const PointLoad& load) {
  const int n = model.num_coordinates();
  const Jacobians J = com_jacobians(model, z);
  const Poses P0 = poses(model, z, zd);
  Eigen::VectorXd Q = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n; ++j) {
    const Body& body = model.bodies[j];
    // Velocity-product accelerations: d/dt of the (exact) velocities along
    // z(t) = z + zd t, i.e. with zdd = 0.
    const auto com_velocity = [&](double t) -> Eigen::Vector3d {
      const Poses P = poses(model, z + t * zd, zd);
      return rate_of_point(P.Tdot[j], body.com_B);
    };
    const auto omega_at = [&](double t) -> Eigen::Vector3d {
      const Poses P = poses(model, z + t * zd, zd);
      return angular_rate(P.T[j], P.Tdot[j]);
    };
    const Eigen::Vector3d a_bias = derivative(com_velocity, kTimeStep);
    const Eigen::Vector3d alpha_bias = derivative(omega_at, kTimeStep);

    const Eigen::Matrix3d R = P0.T[j].topLeftCorner<3, 3>();
    const Eigen::Matrix3d Jw = R * body.inertia_B * R.transpose();
    const Eigen::Vector3d omega = angular_rate(P0.T[j], P0.Tdot[j]);
    const Eigen::Vector3d g = transform_point(P0.T[j], body.com_B);

    Eigen::Vector3d f = body.mass * model.gravity;
    Eigen::Vector3d tau = Eigen::Vector3d::Zero();
    if (load.point.body == j) {
      f += load.F;
      tau += (transform_point(P0.T[j], load.point.p_B) - g).cross(load.F);
    }
    Q += J.v[j].transpose() * (f - body.mass * a_bias) +
         J.w[j].transpose() * (tau - Jw * alpha_bias - omega.cross(Jw * omega));
  }
  return Q;
}

// Lagrange's equations: M zdd = Q_applied - (Mdot zd - 1/2 d/dz (zd^T M zd)).
Eigen::VectorXd reference_forces_lagrange(const Model& model, const Eigen::VectorXd& z,
                                          const Eigen::VectorXd& zd, const PointLoad& load) {
  const int n = model.num_coordinates();
  const Eigen::VectorXd Mdot_zd = derivative(
      [&](double t) -> Eigen::VectorXd { return reference_mass_matrix(model, z + t * zd) * zd; },
      kTimeStep);
  Eigen::VectorXd dT_dz(n);
  for (int k = 0; k < n; ++k) {
    const auto twice_T = [&](double e) -> Eigen::Matrix<double, 1, 1> {
      const Eigen::VectorXd zk = z + e * Eigen::VectorXd::Unit(n, k);
      return Eigen::Matrix<double, 1, 1>(zd.dot(reference_mass_matrix(model, zk) * zd));
    };
    dT_dz[k] = 0.5 * derivative(twice_T, kTimeStep)(0);
  }
  return reference_applied_force(model, z, load) - (Mdot_zd - dT_dz);
}

// The semirecursive result under test.
void semirecursive(const Model& model, Data& data, const Eigen::VectorXd& z,
                   const Eigen::VectorXd& zd, const PointLoad& load) {
  forward_kinematics(model, data, z, zd);
  reset_applied_forces(model, data);
  if (load.point.body != kGround) {
    apply_point_force(data, load.point.body, point_position(data, load.point), load.F);
  }
  mass_matrix_and_forces(model, data);
}

double relative_error(const Eigen::MatrixXd& got, const Eigen::MatrixXd& expected) {
  return (got - expected).norm() / std::max(1.0, expected.norm());
}

constexpr unsigned kSeeds[] = {11u, 23u, 37u, 41u, 59u};

struct RandomCase {
  Model model;
  Eigen::VectorXd z, zd;
  PointLoad load;
};

RandomCase random_case(unsigned seed) {
  Rng rng(seed);
  RandomCase c;
  c.model = random_tree(rng);
  const int n = c.model.num_coordinates();
  c.z = random_vector(rng, n, -kPi, kPi);
  c.zd = random_vector(rng, n, -2.0, 2.0);
  c.load.point.body = rng.integer(0, n - 1);
  c.load.point.p_B = rng.vector(-1.0, 1.0);
  c.load.F = rng.vector(-20.0, 20.0);
  return c;
}

// ------------------------------------------------------------------ the tests

TEST(OpenLoopDynamics, ForwardKinematicsPlacesBodiesAsComposedTransforms) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    const std::vector<Mat4<double>> T = body_transforms<double>(c.model, c.z);
    for (int j = 0; j < c.model.num_bodies(); ++j) {
      EXPECT_LT((data.R_W_B[j] - T[j].topLeftCorner<3, 3>()).norm(), 1e-13) << seed;
      EXPECT_LT((data.o_W[j] - T[j].topRightCorner<3, 1>()).norm(), 1e-13) << seed;
      EXPECT_LT((data.g_W[j] - transform_point(T[j], c.model.bodies[j].com_B)).norm(), 1e-13)
          << seed;
    }
  }
}

// Tolerances: M' is compared with complex-step Jacobians (exact to rounding),
// so 1e-12 relative; Q' involves a fourth-order time difference (h = 1e-3),
// so 1e-9 relative (errors seen are below 2e-12).
TEST(OpenLoopDynamics, MassMatrixOnRandomTreesEqualsAbsoluteCoordinateJacobianSum) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    const Eigen::MatrixXd M_ref = reference_mass_matrix(c.model, c.z);
    const double err = relative_error(data.M, M_ref);
    EXPECT_LT(err, 1e-12) << "seed " << seed << "\nM'=\n" << data.M << "\nref=\n" << M_ref;
    RecordProperty("seed" + std::to_string(seed) + "_M_rel_err", scientific(err));
  }
}

TEST(OpenLoopDynamics, ForcesOnRandomTreesEqualAbsoluteNewtonEulerProjection) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    const Eigen::VectorXd Q_ref = reference_forces_newton_euler(c.model, c.z, c.zd, c.load);
    const double err = relative_error(data.Q, Q_ref);
    EXPECT_LT(err, 1e-9) << "seed " << seed << "\nQ'=" << data.Q.transpose()
                         << "\nref=" << Q_ref.transpose();
    RecordProperty("seed" + std::to_string(seed) + "_Q_NE_rel_err", scientific(err));
  }
}

// Lagrange's equations with the reference M(z) differentiated in z and in time
// (fourth-order stencils, h = 1e-3): 1e-9 relative.
TEST(OpenLoopDynamics, ForcesOnRandomTreesEqualLagrangeEquations) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    const Eigen::VectorXd Q_ref = reference_forces_lagrange(c.model, c.z, c.zd, c.load);
    const double err = relative_error(data.Q, Q_ref);
    EXPECT_LT(err, 1e-9) << "seed " << seed << "\nQ'=" << data.Q.transpose()
                         << "\nref=" << Q_ref.transpose();
    RecordProperty("seed" + std::to_string(seed) + "_Q_Lagrange_rel_err", scientific(err));
  }
}

TEST(OpenLoopDynamics, MassMatrixIsSymmetricPositiveDefinite) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    EXPECT_LT((data.M - data.M.transpose()).norm(), 1e-14 * data.M.norm()) << seed;
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(data.M).info(), Eigen::Success) << seed;
  }
}

TEST(OpenLoopDynamics, KineticEnergyEqualsHalfZdTransposeMassMatrixZd) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    const double T = kinetic_energy(c.model, data);
    const double T_M = 0.5 * c.zd.dot(data.M * c.zd);
    EXPECT_GT(T, 0.0);
    EXPECT_NEAR(T, T_M, 1e-12 * T) << seed;
  }
}

// inverse_dynamics's O(N) recursion gives Eq. (12)'s M' zdd - Q' with every
// velocity term and an applied point force: the same equations summed in
// another order, so to round-off. It leaves data.M and data.Q as they were.
TEST(OpenLoopDynamics, InverseDynamicsOnRandomTreesEqualsMassMatrixTimesZddLessForces) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    const int n = c.model.num_coordinates();
    Rng rng(seed + 1000u);
    const Eigen::VectorXd zdd = random_vector(rng, n, -5.0, 5.0);
    Data data(c.model);
    semirecursive(c.model, data, c.z, c.zd, c.load);
    const Eigen::VectorXd expected = data.M * zdd - data.Q;
    const Eigen::MatrixXd M = data.M;
    Eigen::VectorXd r(n);
    inverse_dynamics(c.model, data, zdd, r);
    const double scale =
        (data.M * zdd).lpNorm<Eigen::Infinity>() + data.Q.lpNorm<Eigen::Infinity>();
    EXPECT_LT((r - expected).lpNorm<Eigen::Infinity>(), 1e-13 * scale) << seed;
    EXPECT_EQ(data.M, M) << seed;
  }
  Data data(random_case(kSeeds[0]).model);
  Eigen::VectorXd short_r(1);
  EXPECT_THROW(inverse_dynamics(
                   random_case(kSeeds[0]).model, data,
                   Eigen::VectorXd::Zero(random_case(kSeeds[0]).model.num_coordinates()), short_r),
               std::invalid_argument);
}

// At rest with gravity only, Q' is the gravity generalized force -dV/dz
// (fourth-order difference of potential_energy, h = 1e-3: 1e-9 relative).
TEST(OpenLoopDynamics, ForcesAtRestEqualMinusPotentialEnergyGradient) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    const int n = c.model.num_coordinates();
    const Eigen::VectorXd rest = Eigen::VectorXd::Zero(n);
    Data data(c.model);
    semirecursive(c.model, data, c.z, rest, PointLoad{});
    Data probe(c.model);
    Eigen::VectorXd grad(n);
    for (int k = 0; k < n; ++k) {
      grad[k] = derivative(
          [&](double e) -> Eigen::Matrix<double, 1, 1> {
            forward_kinematics(c.model, probe, c.z + e * Eigen::VectorXd::Unit(n, k), rest);
            return Eigen::Matrix<double, 1, 1>(potential_energy(c.model, probe));
          },
          kTimeStep)(0);
    }
    EXPECT_LT(relative_error(data.Q, -grad), 1e-9)
        << seed << "\nQ'=" << data.Q.transpose() << "\n-dV/dz=" << -grad.transpose();
  }
}

// Without gravity and at rest, a point force F enters as J_p^T F.
TEST(OpenLoopDynamics, PointForceAtRestGivesJacobianTransposeTimesForce) {
  for (unsigned seed : kSeeds) {
    RandomCase c = random_case(seed);
    c.model.gravity.setZero();
    const int n = c.model.num_coordinates();
    Data data(c.model);
    semirecursive(c.model, data, c.z, Eigen::VectorXd::Zero(n), c.load);
    Matrix3Xd Jp(3, n);
    point_jacobian(c.model, data, c.load.point, Jp);
    const Eigen::VectorXd expected = Jp.transpose() * c.load.F;
    EXPECT_LT(relative_error(data.Q, expected), 1e-13) << seed;
  }
}

// A rod of length L and mass m on a revolute joint about Z, gravity -Y. The
// pivot is away from the world origin and the rod swings, which exercises the
// sdot terms of Z and of Eq. (10): M' = m L^2/3, Q' = -m g L/2 cos z exactly.
TEST(OpenLoopDynamics, RevolutePendulumMatchesClosedForm) {
  const double L = 1.3, m = 2.1, g = 9.81;
  Model model;
  Body rod;
  rod.joint = JointType::revolute;
  rod.joint_P = Eigen::Vector3d(0.4, -0.7, 0.25);
  rod.axis_P = Eigen::Vector3d::UnitZ();
  rod.mass = m;
  rod.com_B = Eigen::Vector3d(L / 2.0, 0.0, 0.0);
  rod.inertia_B = Eigen::Vector3d(0.0, m * L * L / 12.0, m * L * L / 12.0).asDiagonal();
  model.bodies.push_back(rod);
  model.gravity = Eigen::Vector3d(0.0, -g, 0.0);
  Data data(model);
  for (double z : {0.0, 0.3, -1.2, 2.5}) {
    for (double zd : {0.0, 1.7, -3.0}) {
      semirecursive(model, data, Eigen::VectorXd::Constant(1, z), Eigen::VectorXd::Constant(1, zd),
                    PointLoad{});
      EXPECT_NEAR(data.M(0, 0), m * L * L / 3.0, 1e-13) << z << " " << zd;
      EXPECT_NEAR(data.Q(0), -m * g * L / 2.0 * std::cos(z), 1e-12) << z << " " << zd;
    }
  }
}

// A body sliding along a fixed axis: M' = m and Q' = m gravity . axis whatever
// its orientation, COM offset, inertia, position or speed.
TEST(OpenLoopDynamics, PrismaticSliderMatchesClosedForm) {
  Rng rng(7u);
  Model model;
  Body slider;
  slider.joint = JointType::prismatic;
  slider.joint_P = Eigen::Vector3d(0.3, 1.1, -0.6);
  slider.axis_P = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  slider.R_P_B0 = rng.rotation();
  slider.mass = 3.4;
  slider.com_B = Eigen::Vector3d(0.2, -0.4, 0.7);
  slider.inertia_B = rng.inertia();
  model.bodies.push_back(slider);
  model.gravity = Eigen::Vector3d(0.5, -9.81, 1.2);
  Data data(model);
  for (double z : {0.0, 0.8, -2.0}) {
    for (double zd : {0.0, 1.5, -4.0}) {
      semirecursive(model, data, Eigen::VectorXd::Constant(1, z), Eigen::VectorXd::Constant(1, zd),
                    PointLoad{});
      EXPECT_NEAR(data.M(0, 0), slider.mass, 1e-13);
      EXPECT_NEAR(data.Q(0), slider.mass * model.gravity.dot(slider.axis_P), 1e-12);
    }
  }
}

TEST(OpenLoopDynamics, PointForceMomentIsTakenAboutTheCentreOfMass) {
  Rng rng(3u);
  const Model model = random_tree(rng);
  Data data(model);
  const int n = model.num_coordinates();
  forward_kinematics(model, data, random_vector(rng, n, -1.0, 1.0), Eigen::VectorXd::Zero(n));
  reset_applied_forces(model, data);
  const Eigen::Vector3d F(1.0, -2.0, 3.0);
  const Eigen::Vector3d arm(0.5, 0.25, -1.0);
  apply_point_force(data, 2, data.g_W[2] + arm, F);
  apply_body_moment(data, 2, Eigen::Vector3d(0.0, 0.0, 4.0));
  apply_point_force(data, kGround, Eigen::Vector3d::Zero(), F);  // ignored
  EXPECT_LT((data.f_W[2] - (model.bodies[2].mass * model.gravity + F)).norm(), 1e-14);
  EXPECT_LT((data.tau_W[2] - (arm.cross(F) + Eigen::Vector3d(0.0, 0.0, 4.0))).norm(), 1e-14);
  EXPECT_EQ(data.tau_W[1], Eigen::Vector3d::Zero());
}

TEST(OpenLoopDynamics, DataOfAnotherModelThrowsExpectedSize) {
  Rng rng(5u);
  Model small = random_tree(rng);
  Model large = small;
  large.bodies.push_back(small.bodies.back());
  Data data(small);
  try {
    mass_matrix_and_forces(large, data);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
  }
  EXPECT_THROW(kinetic_energy(large, data), std::invalid_argument);
  EXPECT_THROW(
      apply_point_force(data, small.num_bodies(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
      std::invalid_argument);
}

}  // namespace
}  // namespace mh
