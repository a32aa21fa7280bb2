// Cut-joint constraints: Phi vanishes on the case studies' geometry, Phi_z
// and the velocity-product term equal finite differences on planar and 3D
// models, and loops are assembled from rounded initial angles.
#include "monohydra/core/constraints.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "constraint_eval.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using Eval = test::ConstraintEval;
using test::evaluate;

Constraints build_at(const Model& model, const Eigen::VectorXd& z) {
  Data data(model);
  forward_kinematics(model, data, z, Eigen::VectorXd::Zero(model.num_coordinates()));
  return build_constraints(model, data);
}

// Phi_z against central differences of Phi, and Phi_z_dot zd against the
// second time derivative of Phi along z(t) = z + zd t (zdd = 0).
void expect_derivatives_match(const Model& model, Constraints& cs, const Eigen::VectorXd& z,
                              const Eigen::VectorXd& zd) {
  const int N = model.num_coordinates();
  const Eval e = evaluate(model, cs, z, zd);
  const double h = 1e-6;
  for (int j = 0; j < N; ++j) {
    Eigen::VectorXd zp = z, zm = z;
    zp[j] += h;
    zm[j] -= h;
    const Eigen::VectorXd col =
        (evaluate(model, cs, zp, zd).phi - evaluate(model, cs, zm, zd).phi) / (2.0 * h);
    EXPECT_LT((col - e.phi_z.col(j)).norm(), 1e-8 * (1.0 + col.norm())) << "column " << j;
  }
  const double ht = 1e-4;
  const Eigen::VectorXd second = (evaluate(model, cs, z + ht * zd, zd).phi - 2.0 * e.phi +
                                  evaluate(model, cs, z - ht * zd, zd).phi) /
                                 (ht * ht);
  EXPECT_LT((second - e.phi_dot).norm(), 1e-5 * (1.0 + second.norm()));
}

TEST(Constraints, FourBarClosesExactlyAtThePapersInitialAngles) {
  const ModelFile f = load_model_file(test::source_path("models/fourbar-free.yaml"));
  const Eigen::VectorXd z0 = f.model.initial_coordinates();
  Constraints cs = build_at(f.model, z0);
  ASSERT_EQ(cs.size(), 2);  // planar revolute: two rows
  EXPECT_LT(evaluate(f.model, cs, z0, Eigen::VectorXd::Zero(3)).phi.norm(), 1e-12);
}

TEST(Constraints, PlanarJacobianAndVelocityProductMatchFiniteDifferences) {
  for (const char* name : {"models/fourbar-free.yaml", "models/quickreturn-free.yaml",
                           "models/parallelogram-redundant.yaml"}) {
    SCOPED_TRACE(name);
    const ModelFile f = load_model_file(test::source_path(name));
    const int N = f.model.num_coordinates();
    test::Rng rng(3);
    const Eigen::VectorXd z =
        f.model.initial_coordinates() + test::random_vector(rng, N, -0.1, 0.1);
    const Eigen::VectorXd zd = test::random_vector(rng, N, -1.0, 1.0);
    Constraints cs = build_at(f.model, z);
    expect_derivatives_match(f.model, cs, z, zd);
  }
}

// A random 3D tree of six bodies with one cut joint of each kind between
// random points of its bodies.
Model random_3d_model(test::Rng& rng) {
  Model m = test::random_tree(rng, 6, 6);
  const CutJointType types[] = {CutJointType::revolute, CutJointType::spherical,
                                CutJointType::translational};
  for (int k = 0; k < 3; ++k) {
    CutJoint cj;
    cj.name = "c" + std::to_string(k);
    cj.type = types[k];
    cj.a = BodyPoint{k, rng.vector(-1.0, 1.0)};
    cj.b = BodyPoint{k == 0 ? kGround : 5 - k, rng.vector(-1.0, 1.0)};
    cj.axis_a = rng.unit_vector();
    cj.axis_b = rng.unit_vector();
    m.cut_joints.push_back(cj);
  }
  return m;
}

TEST(Constraints, SpatialJacobianAndVelocityProductMatchFiniteDifferences) {
  test::Rng rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    const Model m = random_3d_model(rng);
    const Eigen::VectorXd z = test::random_vector(rng, 6, -1.0, 1.0);
    const Eigen::VectorXd zd = test::random_vector(rng, 6, -1.0, 1.0);
    Constraints cs = build_at(m, z);
    ASSERT_EQ(cs.size(), 5 + 3 + 5);  // revolute, spherical, translational in 3D
    expect_derivatives_match(m, cs, z, zd);
  }
}

TEST(Constraints, TranslationalTwistRowVanishesWhereItWasBuilt) {
  test::Rng rng(5);
  const Model m = random_3d_model(rng);
  const Eigen::VectorXd z = Eigen::VectorXd::Constant(6, 0.3);
  Constraints cs = build_at(m, z);
  const Eval e = evaluate(m, cs, z, Eigen::VectorXd::Zero(6));
  EXPECT_NEAR(e.phi[12], 0.0, 1e-14);  // the last row locks the initial twist
}

TEST(Constraints, QuickReturnAssemblesFromRoundedAnglesHoldingTheCrank) {
  const ModelFile f = load_model_file(test::source_path("models/quickreturn-free.yaml"));
  Simulation sim(f, test::build_plugins(), "penalty");
  sim.start();
  EXPECT_LT(sim.phi_norm(), 1e-12);
  const double deg = M_PI / 180.0;
  const Eigen::VectorXd& z = sim.z();
  EXPECT_NEAR(z[3], 30.59 * deg, 1e-15);  // the crank is held
  // Absolute angles of case-studies.md: 76.22, 173.11, 180.00, 30.59, 76.22 deg.
  EXPECT_NEAR(z[0], 76.22 * deg, 0.01 * deg);
  EXPECT_NEAR(z[0] + z[1], 173.11 * deg, 0.01 * deg);
  EXPECT_NEAR(z[0] + z[1] + z[2], M_PI, 0.01 * deg);
  EXPECT_NEAR(z[3] + z[4], z[0], 1e-12);  // the block is aligned with the rocker
}

}  // namespace
}  // namespace mh
