// The articulated-body solve of M' x = y (articulated_solve.hpp) against the
// dense M' of Eq. (12) (mass_matrix_and_forces, itself tested against an
// independent absolute-coordinate computation in dynamics_test.cpp).
#include "monohydra/core/articulated_solve.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <string>

#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::random_tree;
using test::random_vector;
using test::Rng;

// M' x for the dense M' at the same kinematics.
Eigen::VectorXd times_mass(const Model& model, Data& data, const Eigen::VectorXd& x) {
  reset_applied_forces(model, data);
  mass_matrix_and_forces(model, data);
  return data.M * x;
}

TEST(ArticulatedSolve, GivesTheDenseMassMatrixsSolutionOnRandomTreesOfBothJointTypes) {
  Rng rng(20261205);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const Model model = random_tree(rng, 3, 24);
    Data data(model);
    const int n = model.num_coordinates();
    forward_kinematics(model, data, random_vector(rng, n, -2.0, 2.0),
                       random_vector(rng, n, -1.0, 1.0));
    ArticulatedWorkspace ws(model);
    ASSERT_TRUE(articulated_factor(model, data, ws));
    const Eigen::VectorXd x_true = random_vector(rng, n, -1.0, 1.0);
    Eigen::VectorXd y = times_mass(model, data, x_true);
    articulated_solve(model, ws, y);
    // M' is symmetric positive definite here: its LDLT's answer is the
    // reference the error is weighed against.
    const Eigen::VectorXd x_ldlt = data.M.ldlt().solve(data.M * x_true);
    const double err = (y - x_true).lpNorm<Eigen::Infinity>();
    const double ref = (x_ldlt - x_true).lpNorm<Eigen::Infinity>();
    worst = std::max(worst, err / x_true.lpNorm<Eigen::Infinity>());
    EXPECT_LT(err, 1e-9 * x_true.lpNorm<Eigen::Infinity>() + 100.0 * ref) << "trial " << trial;
  }
  ::testing::Test::RecordProperty("worst_relative_error", test::scientific(worst));
}

// A chain's M' is dense and ill-conditioned (its error in x grows with the
// condition number whatever the method), but the recursion is backward
// stable: M' x reproduces y to round-off for 2000 bodies as for four.
TEST(ArticulatedSolve, SolvesADenseChainOfTwoThousandBodies) {
  Model model;
  for (int j = 0; j < 2000; ++j) {
    Body b;
    b.name = "b" + std::to_string(j);
    b.parent = j - 1;
    b.joint_P = j == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.1, 0.0, 0.0);
    b.mass = 1.0;
    b.com_B = Eigen::Vector3d(0.05, 0.0, 0.0);
    b.inertia_B = Eigen::Vector3d(1e-4, 8.4e-4, 8.4e-4).asDiagonal();
    model.bodies.push_back(b);
  }
  Data data(model);
  Rng rng(7);
  const int n = model.num_coordinates();
  forward_kinematics(model, data, random_vector(rng, n, -0.3, 0.3), random_vector(rng, n, -1, 1));
  ArticulatedWorkspace ws(model);
  ASSERT_TRUE(articulated_factor(model, data, ws));
  const Eigen::VectorXd x_true = random_vector(rng, n, -1.0, 1.0);
  const Eigen::VectorXd y0 = times_mass(model, data, x_true);
  Eigen::VectorXd x = y0;
  articulated_solve(model, ws, x);
  const double backward = (data.M * x - y0).lpNorm<Eigen::Infinity>() /
                          (data.M.lpNorm<Eigen::Infinity>() * x.lpNorm<Eigen::Infinity>());
  ::testing::Test::RecordProperty("backward_error", test::scientific(backward));
  EXPECT_LT(backward, 1e-12);
}

// A body without mass at the end of a chain leaves its joint without
// inertia: refused, not divided by zero.
TEST(ArticulatedSolve, AJointWithoutInertiaIsRefused) {
  Model model;
  for (int j = 0; j < 3; ++j) {
    Body b;
    b.parent = j - 1;
    b.joint_P = Eigen::Vector3d(j == 0 ? 0.0 : 0.1, 0.0, 0.0);
    b.mass = j == 2 ? 0.0 : 1.0;
    b.com_B = Eigen::Vector3d(0.05, 0.0, 0.0);
    b.inertia_B = Eigen::Matrix3d::Identity() * (j == 2 ? 0.0 : 1e-3);
    model.bodies.push_back(b);
  }
  Data data(model);
  forward_kinematics(model, data, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3));
  ArticulatedWorkspace ws(model);
  EXPECT_FALSE(articulated_factor(model, data, ws));
}

}  // namespace
}  // namespace mh
