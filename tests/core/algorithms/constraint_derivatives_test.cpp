// Tests of the analytic derivatives of the cut-joint terms: d(Phi_z^T v)/dz
// and the derivatives of A = Phi_z zdd + Phi_z_dot zd against central
// differences of evaluate_constraints, on random 3D trees with random cut
// joints of every type and on the planar case-study models.
#include "monohydra/core/constraint_derivatives.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "constraint_eval.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model_file.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::random_tree;
using test::random_vector;
using test::Rng;

using Eval = test::ConstraintEval;
using test::evaluate;

Eigen::VectorXd accelerations(const Model& model, Constraints& cs, const Eigen::VectorXd& z,
                              const Eigen::VectorXd& zd, const Eigen::VectorXd& zdd) {
  const Eval e = evaluate(model, cs, z, zd);
  return e.phi_z * zdd + e.phi_dot;
}

Constraints build_at(const Model& model, const Eigen::VectorXd& z) {
  Data data(model);
  forward_kinematics(model, data, z, Eigen::VectorXd::Zero(model.num_coordinates()));
  return build_constraints(model, data);
}

double relative(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
  return (got - want).cwiseAbs().maxCoeff() / std::max(want.cwiseAbs().maxCoeff(), 1e-300);
}

struct Errors {
  double force = 0.0, dA_dz = 0.0, dA_dzd = 0.0, asymmetry = 0.0;
  void worst_of(const Errors& e) {
    force = std::max(force, e.force);
    dA_dz = std::max(dA_dz, e.dA_dz);
    dA_dzd = std::max(dA_dzd, e.dA_dzd);
    asymmetry = std::max(asymmetry, e.asymmetry);
  }
};

Errors compare(const Model& model, Constraints& cs, const Eigen::VectorXd& z,
               const Eigen::VectorXd& zd, const Eigen::VectorXd& zdd, const Eigen::VectorXd& v) {
  const int N = model.num_coordinates();
  const int m = cs.size();
  Data data(model);
  forward_kinematics(model, data, z, zd);
  ConstraintDerivativesWorkspace ws(model);
  Eigen::MatrixXd G(N, N), dA_dz(m, N), dA_dzd(m, N);
  constraint_force_derivative(model, data, cs, v, ws, G);
  constraint_acceleration_derivatives(model, data, cs, zdd, ws, dA_dz, dA_dzd);

  const double h = 1e-6;
  Eigen::MatrixXd G_fd(N, N), dA_dz_fd(m, N), dA_dzd_fd(m, N);
  for (int k = 0; k < N; ++k) {
    Eigen::VectorXd dz = Eigen::VectorXd::Zero(N);
    dz[k] = h;
    G_fd.col(k) = (evaluate(model, cs, z + dz, zd).phi_z.transpose() * v -
                   evaluate(model, cs, z - dz, zd).phi_z.transpose() * v) /
                  (2.0 * h);
    dA_dz_fd.col(k) =
        (accelerations(model, cs, z + dz, zd, zdd) - accelerations(model, cs, z - dz, zd, zdd)) /
        (2.0 * h);
    dA_dzd_fd.col(k) =
        (accelerations(model, cs, z, zd + dz, zdd) - accelerations(model, cs, z, zd - dz, zdd)) /
        (2.0 * h);
  }
  Errors e;
  e.force = relative(G, G_fd);
  e.dA_dz = relative(dA_dz, dA_dz_fd);
  e.dA_dzd = relative(dA_dzd, dA_dzd_fd);
  e.asymmetry = relative(G, G.transpose());
  return e;
}

void expect_small(const Errors& e, const std::string& where) {
  EXPECT_LT(e.force, 1e-6) << where;
  EXPECT_LT(e.dA_dz, 1e-6) << where;
  EXPECT_LT(e.dA_dzd, 1e-6) << where;
  EXPECT_LT(e.asymmetry, 1e-14) << where;  // a sum of Hessians: symmetric to rounding
}

// A random 3D tree of 4 to 10 bodies with 2 to 5 cut joints of random types
// between random points of random bodies or the ground (never both on the ground).
Model random_closed_model(Rng& rng) {
  Model model = random_tree(rng, 4, 10);
  const int n = model.num_bodies();
  const CutJointType types[] = {CutJointType::revolute, CutJointType::spherical,
                                CutJointType::translational};
  const int joints = rng.integer(2, 5);
  for (int k = 0; k < joints; ++k) {
    CutJoint cj;
    cj.name = "c" + std::to_string(k);
    cj.type = k < 3 ? types[k] : types[rng.integer(0, 2)];  // every type at least once
    cj.a = BodyPoint{rng.integer(kGround, n - 1), rng.vector(-1.0, 1.0)};
    cj.b = BodyPoint{rng.integer(cj.a.body == kGround ? 0 : kGround, n - 1), rng.vector(-1.0, 1.0)};
    cj.axis_a = rng.unit_vector();
    cj.axis_b = rng.unit_vector();
    model.cut_joints.push_back(cj);
  }
  return model;
}

TEST(ConstraintDerivatives, ForceAndAccelerationDerivativesMatchCentralDifferencesOnRandom3DTrees) {
  Rng rng(2021);
  Errors worst;
  for (int trial = 0; trial < 40; ++trial) {
    const Model model = random_closed_model(rng);
    const int N = model.num_coordinates();
    const Eigen::VectorXd z = random_vector(rng, N, -3.0, 3.0);
    Constraints cs = build_at(model, random_vector(rng, N, -3.0, 3.0));
    const Eigen::VectorXd v = random_vector(rng, cs.size(), -10.0, 10.0);
    const Errors e = compare(model, cs, z, random_vector(rng, N, -2.0, 2.0),
                             random_vector(rng, N, -3.0, 3.0), v);
    expect_small(e, "trial " + std::to_string(trial));
    worst.worst_of(e);
  }
  std::printf(
      "[ measured ] random 3D trees: max relative error d(Phi_z^T v)/dz %.2e, "
      "dA/dz %.2e, dA/dzd %.2e\n",
      worst.force, worst.dA_dz, worst.dA_dzd);
}

TEST(ConstraintDerivatives, ForceAndAccelerationDerivativesMatchCentralDifferencesOnPlanarModels) {
  Errors worst;
  for (const char* name : {"models/fourbar-free.yaml", "models/quickreturn-free.yaml",
                           "models/parallelogram-redundant.yaml", "models/crank-rocker.yaml"}) {
    const ModelFile f = load_model_file(test::source_path(name));
    const int N = f.model.num_coordinates();
    Rng rng(3);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd z = f.model.initial_coordinates() + random_vector(rng, N, -0.3, 0.3);
      Constraints cs = build_at(f.model, z);
      ASSERT_GT(cs.size(), 0) << name;
      const Eigen::VectorXd v = random_vector(rng, cs.size(), -10.0, 10.0);
      const Errors e = compare(f.model, cs, z, random_vector(rng, N, -2.0, 2.0),
                               random_vector(rng, N, -3.0, 3.0), v);
      expect_small(e, name);
      worst.worst_of(e);
    }
  }
  std::printf(
      "[ measured ] planar models: max relative error d(Phi_z^T v)/dz %.2e, "
      "dA/dz %.2e, dA/dzd %.2e\n",
      worst.force, worst.dA_dz, worst.dA_dzd);
}

// At zd = 0 the velocity-product term and its z-derivative vanish, so
// dA/dz = d(Phi_z zdd)/dz, and dA/dzd = 2 zd^T Hessian = 0.
TEST(ConstraintDerivatives, AtRestAccelerationDerivativesReduceToJacobianDerivative) {
  Rng rng(17);
  for (int trial = 0; trial < 10; ++trial) {
    const Model model = random_closed_model(rng);
    const int N = model.num_coordinates();
    const Eigen::VectorXd z = random_vector(rng, N, -3.0, 3.0);
    Constraints cs = build_at(model, z);
    const int m = cs.size();
    const Eigen::VectorXd zdd = random_vector(rng, N, -3.0, 3.0);
    Data data(model);
    forward_kinematics(model, data, z, Eigen::VectorXd::Zero(N));
    ConstraintDerivativesWorkspace ws(model);
    Eigen::MatrixXd dA_dz(m, N), dA_dzd(m, N), G(N, N);
    constraint_acceleration_derivatives(model, data, cs, zdd, ws, dA_dz, dA_dzd);
    EXPECT_EQ(dA_dzd.cwiseAbs().maxCoeff(), 0.0);
    // Row i of d(Phi_z zdd)/dz is zdd^T Hessian_i: d(Phi_z^T e_i)/dz times zdd.
    for (int i = 0; i < m; ++i) {
      constraint_force_derivative(model, data, cs, Eigen::VectorXd::Unit(m, i), ws, G);
      const Eigen::RowVectorXd row = (G * zdd).transpose();
      EXPECT_LT((dA_dz.row(i) - row).cwiseAbs().maxCoeff(),
                1e-12 * std::max(1.0, row.cwiseAbs().maxCoeff()))
          << "row " << i;
    }
  }
}

TEST(ConstraintDerivatives, WrongSizesThrowInvalidArgument) {
  Rng rng(4);
  const Model model = random_closed_model(rng);
  const int N = model.num_coordinates();
  Constraints cs = build_at(model, Eigen::VectorXd::Zero(N));
  const int m = cs.size();
  Data data(model);
  forward_kinematics(model, data, Eigen::VectorXd::Zero(N), Eigen::VectorXd::Zero(N));
  ConstraintDerivativesWorkspace ws(model);
  Eigen::MatrixXd G(N, N), dA(m, N), wrong(m + 1, N);
  EXPECT_THROW(constraint_force_derivative(model, data, cs, Eigen::VectorXd::Zero(m + 1), ws, G),
               std::invalid_argument);
  EXPECT_THROW(
      constraint_acceleration_derivatives(model, data, cs, Eigen::VectorXd::Zero(N), ws, wrong, dA),
      std::invalid_argument);
  EXPECT_NO_THROW(
      constraint_acceleration_derivatives(model, data, cs, Eigen::VectorXd::Zero(N), ws, dA, dA));
}

}  // namespace
}  // namespace mh
