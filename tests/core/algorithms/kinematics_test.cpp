// Tests of the open-loop semirecursive kinematics (Sect. 2.1, Eqs. 1-7): point
// velocities and accelerations must be the time derivatives of the positions
// that forward_kinematics produces, and the Jacobians must reproduce them.
#include "monohydra/core/kinematics.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/data.hpp"
#include "monohydra/core/model.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using Matrix3Xd = Eigen::Matrix<double, 3, Eigen::Dynamic>;
constexpr double kPi = 3.14159265358979323846;

using test::random_tree;
using test::random_vector;
using test::Rng;
using test::scientific;

struct RandomCase {
  Model model;
  Eigen::VectorXd z, zd, zdd;
  std::vector<BodyPoint> points;  // one per body, plus a ground point
};

RandomCase random_case(unsigned seed) {
  Rng rng(seed);
  RandomCase c;
  c.model = random_tree(rng);
  const int n = c.model.num_coordinates();
  c.z = random_vector(rng, n, -kPi, kPi);
  c.zd = random_vector(rng, n, -2.0, 2.0);
  c.zdd = random_vector(rng, n, -5.0, 5.0);
  for (int j = kGround; j < n; ++j) c.points.push_back(BodyPoint{j, rng.vector(-1.0, 1.0)});
  return c;
}

constexpr unsigned kSeeds[] = {11u, 23u, 37u, 41u, 59u};

// f'(0) and f''(0) by fourth-order central stencils.
template <class F>
Eigen::Vector3d first_derivative(F f, double h) {
  return (f(-2.0 * h) - 8.0 * f(-h) + 8.0 * f(h) - f(2.0 * h)) / (12.0 * h);
}
template <class F>
Eigen::Vector3d second_derivative(F f, double h) {
  return (-f(-2.0 * h) + 16.0 * f(-h) - 30.0 * f(0.0) + 16.0 * f(h) - f(2.0 * h)) / (12.0 * h * h);
}

double relative_error(const Eigen::Vector3d& got, const Eigen::Vector3d& expected) {
  return (got - expected).norm() / std::max(1.0, expected.norm());
}

// Tolerance: fourth-order first difference, h = 1e-3: 1e-9 relative.
// New rates at unchanged positions (kinematics_at in the host): the velocity
// level alone gives what the full pass gives, bit for bit.
TEST(OpenLoopKinematics, VelocityLevelPassEqualsFullPassBitForBit) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Rng rng(seed + 1000u);
    const Eigen::VectorXd zd2 = random_vector(rng, c.model.num_coordinates(), -2.0, 2.0);
    Data full(c.model), fast(c.model);
    forward_kinematics(c.model, full, c.z, zd2);
    forward_kinematics(c.model, fast, c.z, c.zd);
    forward_velocities(c.model, fast, zd2);
    for (int j = 0; j < c.model.num_bodies(); ++j) {
      const auto k = static_cast<size_t>(j);
      EXPECT_EQ(fast.Z[k], full.Z[k]) << "seed " << seed << ", body " << j;
      EXPECT_EQ(fast.d[k], full.d[k]) << "seed " << seed << ", body " << j;
      EXPECT_EQ(fast.Zdot0[k], full.Zdot0[k]) << "seed " << seed << ", body " << j;
      EXPECT_EQ(fast.R_W_B[k], full.R_W_B[k]) << "seed " << seed << ", body " << j;
    }
    EXPECT_EQ(fast.zd, zd2);
    EXPECT_NE(full.Z.back(), Data(c.model).Z.back());  // the rates did move the bodies
  }
}

TEST(OpenLoopKinematics, PointVelocityIsTimeDerivativeOfPointPosition) {
  double worst = 0.0;
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    Data probe(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    for (const BodyPoint& point : c.points) {
      const Eigen::Vector3d fd = first_derivative(
          [&](double t) -> Eigen::Vector3d {
            forward_kinematics(c.model, probe, c.z + t * c.zd, c.zd);
            return point_position(probe, point);
          },
          1e-3);
      const double err = relative_error(point_velocity(data, point), fd);
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-9) << "seed " << seed << " body " << point.body;
    }
  }
  RecordProperty("worst_rel_err", scientific(worst));
}

TEST(OpenLoopKinematics, AngularVelocityIsRateOfBodyRotation) {
  double worst = 0.0;
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    Data probe(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    for (int j = kGround; j < c.model.num_bodies(); ++j) {
      // omega~ = Rdot R^T; take the rotation's derivative column by column.
      Eigen::Matrix3d Rdot;
      for (int col = 0; col < 3; ++col) {
        Rdot.col(col) = first_derivative(
            [&](double t) -> Eigen::Vector3d {
              forward_kinematics(c.model, probe, c.z + t * c.zd, c.zd);
              return body_rotation(probe, j).col(col);
            },
            1e-3);
      }
      const Eigen::Matrix3d W = Rdot * body_rotation(data, j).transpose();
      const Eigen::Vector3d omega(W(2, 1), W(0, 2), W(1, 0));
      const double err = relative_error(body_angular_velocity(data, j), omega);
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-9) << "seed " << seed << " body " << j;
      EXPECT_LT((W + W.transpose()).norm(), 1e-9);  // Rdot R^T is skew
    }
  }
  RecordProperty("worst_rel_err", scientific(worst));
}

TEST(OpenLoopKinematics, PointJacobianTimesRatesEqualsPointVelocity) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    const int n = c.model.num_coordinates();
    Data data(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    Matrix3Xd J(3, n);
    for (const BodyPoint& point : c.points) {
      point_jacobian(c.model, data, point, J);
      EXPECT_LT(relative_error(J * c.zd, point_velocity(data, point)), 1e-14)
          << "seed " << seed << " body " << point.body;
      // Only the joints between the point and the ground can move it.
      for (int k = 0; k < n; ++k) {
        if (!is_ancestor_or_self(c.model, k, point.body)) {
          EXPECT_EQ(J.col(k), Eigen::Vector3d::Zero());
        }
      }
    }
  }
}

TEST(OpenLoopKinematics, AngularJacobianTimesRatesEqualsAngularVelocity) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    Matrix3Xd J(3, c.model.num_coordinates());
    for (int j = kGround; j < c.model.num_bodies(); ++j) {
      angular_jacobian(c.model, data, j, J);
      EXPECT_LT(relative_error(J * c.zd, body_angular_velocity(data, j)), 1e-14);
    }
  }
}

// Along z(t) = z + zd t + zdd t^2/2, the point's second derivative is
// bias + J zdd. Fourth-order second difference, h = 1e-3: 1e-7 relative.
TEST(OpenLoopKinematics, BiasAccelerationPlusJacobianTimesZddIsSecondDerivativeOfPosition) {
  double worst = 0.0;
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    const int n = c.model.num_coordinates();
    Data data(c.model);
    Data probe(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    Matrix3Xd J(3, n);
    for (const BodyPoint& point : c.points) {
      point_jacobian(c.model, data, point, J);
      const Eigen::Vector3d acceleration = point_bias_acceleration(data, point) + J * c.zdd;
      const Eigen::Vector3d fd = second_derivative(
          [&](double t) -> Eigen::Vector3d {
            forward_kinematics(c.model, probe, c.z + t * c.zd + 0.5 * t * t * c.zdd, c.zd);
            return point_position(probe, point);
          },
          1e-3);
      const double err = relative_error(acceleration, fd);
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-7) << "seed " << seed << " body " << point.body << "\ngot "
                           << acceleration.transpose() << "\nfd  " << fd.transpose();
    }
  }
  RecordProperty("worst_rel_err", scientific(worst));
}

// Zdot0 must be the rate of Z along the motion with zdd = 0 (Eq. 5): check it
// on the body twist directly, first-order difference of Z(t) (h = 1e-3, 1e-9).
TEST(OpenLoopKinematics, Zdot0IsTimeDerivativeOfBodyVelocityAtZeroZdd) {
  for (unsigned seed : kSeeds) {
    const RandomCase c = random_case(seed);
    Data data(c.model);
    Data probe(c.model);
    forward_kinematics(c.model, data, c.z, c.zd);
    for (int j = 0; j < c.model.num_bodies(); ++j) {
      for (int half = 0; half < 2; ++half) {
        const Eigen::Vector3d fd = first_derivative(
            [&](double t) -> Eigen::Vector3d {
              forward_kinematics(c.model, probe, c.z + t * c.zd, c.zd);
              return probe.Z[j].segment<3>(3 * half);
            },
            1e-3);
        EXPECT_LT(relative_error(data.Zdot0[j].segment<3>(3 * half), fd), 1e-9)
            << "seed " << seed << " body " << j;
      }
    }
  }
}

TEST(OpenLoopKinematics, GroundPointIsFixed) {
  const RandomCase c = random_case(11u);
  Data data(c.model);
  forward_kinematics(c.model, data, c.z, c.zd);
  const BodyPoint ground{kGround, Eigen::Vector3d(1.0, 2.0, 3.0)};
  EXPECT_EQ(point_position(data, ground), ground.p_B);
  EXPECT_EQ(point_velocity(data, ground), Eigen::Vector3d::Zero());
  EXPECT_EQ(point_bias_acceleration(data, ground), Eigen::Vector3d::Zero());
}

TEST(OpenLoopKinematics, IsAncestorOrSelfFollowsTheTree) {
  Model model;
  for (int parent : {kGround, 0, 1, 0, kGround}) {
    Body body;
    body.parent = parent;
    model.bodies.push_back(body);
  }
  EXPECT_TRUE(is_ancestor_or_self(model, 0, 2));
  EXPECT_TRUE(is_ancestor_or_self(model, 1, 2));
  EXPECT_TRUE(is_ancestor_or_self(model, 2, 2));
  EXPECT_TRUE(is_ancestor_or_self(model, kGround, 4));
  EXPECT_FALSE(is_ancestor_or_self(model, 3, 2));
  EXPECT_FALSE(is_ancestor_or_self(model, 2, 1));
  EXPECT_FALSE(is_ancestor_or_self(model, 0, 4));
  EXPECT_THROW(is_ancestor_or_self(model, 0, 5), std::invalid_argument);
}

void expect_size_error(const std::function<void()>& call) {
  try {
    call();
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
  }
}

TEST(OpenLoopKinematics, SizeMismatchThrowsInvalidArgumentSayingExpected) {
  const RandomCase c = random_case(23u);
  const int n = c.model.num_coordinates();
  Data data(c.model);
  const Eigen::VectorXd short_z = Eigen::VectorXd::Zero(n - 1);
  expect_size_error([&] { forward_kinematics(c.model, data, short_z, c.zd); });
  expect_size_error([&] { forward_kinematics(c.model, data, c.z, short_z); });
  Model other = c.model;
  other.bodies.pop_back();
  Data other_data(other);
  expect_size_error([&] { forward_kinematics(c.model, other_data, c.z, c.zd); });
  forward_kinematics(c.model, data, c.z, c.zd);
  Matrix3Xd narrow(3, n - 1);
  expect_size_error([&] { point_jacobian(c.model, data, c.points[1], narrow); });
  expect_size_error([&] { angular_jacobian(c.model, data, 0, narrow); });
  expect_size_error([&] { point_position(data, BodyPoint{n, Eigen::Vector3d::Zero()}); });
}

}  // namespace
}  // namespace mh
