// The tangent's mechanical pattern from the topology (core/src/algorithms/mechanical_coupling.cpp):
// every nonzero of M', K and C (the analytic fill) and of the residual's
// differences on random trees with point forces lies inside it; without a
// point force's group the same check finds nonzeros outside (the check can
// fail); whole runs' tangents (spring, Maxwell element with its state, a cut
// joint under penalty) differenced centrally have no nonzero outside the
// run's pattern; and a tree of bounded depth has O(N) entries.
#include "monohydra/core/mechanical_coupling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/dynamics_derivatives.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/simulation.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::random_tree;
using test::random_vector;
using test::Rng;

// A zero-length linear spring-damper between two body points: the force on a
// is k (p_b - p_a) + c (v_b - v_a), b gets its opposite.
struct Spring {
  BodyPoint a, b;
  double k = 0.0, c = 0.0;
};

Eigen::Vector3d spring_force(const Spring& s, const Data& data) {
  return s.k * (point_position(data, s.b) - point_position(data, s.a)) +
         s.c * (point_velocity(data, s.b) - point_velocity(data, s.a));
}

std::vector<PointForceTerm> spring_terms(const Spring& s, const Data& data) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  PointForceTerm on_a;
  on_a.point = s.a;
  on_a.F_W = spring_force(s, data);
  on_a.dF_dp = -s.k * I;
  on_a.dF_dv = -s.c * I;
  on_a.other = s.b;
  on_a.dF_dp_other = s.k * I;
  on_a.dF_dv_other = s.c * I;
  PointForceTerm on_b = on_a;
  on_b.point = s.b;
  on_b.other = s.a;
  on_b.F_W = -on_a.F_W;
  on_b.dF_dp = -on_a.dF_dp;
  on_b.dF_dv = -on_a.dF_dv;
  on_b.dF_dp_other = -on_a.dF_dp_other;
  on_b.dF_dv_other = -on_a.dF_dv_other;
  return {on_a, on_b};
}

Eigen::VectorXd residual(const Model& model, const Spring& s, const Eigen::VectorXd& z,
                         const Eigen::VectorXd& zd, const Eigen::VectorXd& zdd) {
  Data data(model);
  forward_kinematics(model, data, z, zd);
  reset_applied_forces(model, data);
  const Eigen::Vector3d F = spring_force(s, data);
  apply_point_force(data, s.a.body, point_position(data, s.a), F);
  apply_point_force(data, s.b.body, point_position(data, s.b), -F);
  mass_matrix_and_forces(model, data);
  return data.M * zdd - data.Q;
}

// The entries of `m` that are nonzero and not in `pattern`, as "name(i, j)".
std::vector<std::string> outside(const Eigen::MatrixXd& m, const char* name,
                                 const std::set<std::pair<int, int>>& pattern) {
  std::vector<std::string> out;
  for (int j = 0; j < m.cols(); ++j)
    for (int i = 0; i < m.rows(); ++i)
      if (m(i, j) != 0.0 && pattern.count({i, j}) == 0)
        out.push_back(std::string(name) + "(" + std::to_string(i) + ", " + std::to_string(j) + ")");
  return out;
}

// Every nonzero of M', K, C and of the central differences of M' zdd - Q' in z
// and zd, outside the pattern built from `groups`.
std::vector<std::string> nonzeros_outside(const Model& model, const Spring& s,
                                          const std::vector<std::vector<int>>& groups, Rng& rng) {
  const int N = model.num_coordinates();
  const Eigen::VectorXd z = random_vector(rng, N, -1.0, 1.0);
  const Eigen::VectorXd zd = random_vector(rng, N, -2.0, 2.0);
  const Eigen::VectorXd zdd = random_vector(rng, N, -3.0, 3.0);
  const auto entries = mechanical_coupling(model, groups);
  const std::set<std::pair<int, int>> pattern(entries.begin(), entries.end());

  Data data(model);
  forward_kinematics(model, data, z, zd);
  reset_applied_forces(model, data);
  mass_matrix_and_forces(model, data);
  const Eigen::MatrixXd M = data.M;
  DynamicsDerivativesWorkspace ws(model);
  Eigen::MatrixXd K(N, N), C(N, N);
  dynamics_derivatives(model, data, zdd, spring_terms(s, data), ws, K, C);
  Eigen::MatrixXd K_cd(N, N), C_cd(N, N);
  const double h = 1e-6;
  for (int k = 0; k < N; ++k) {
    Eigen::VectorXd dz = Eigen::VectorXd::Zero(N);
    dz[k] = h;
    K_cd.col(k) = (residual(model, s, z + dz, zd, zdd) - residual(model, s, z - dz, zd, zdd)) / h;
    C_cd.col(k) = (residual(model, s, z, zd + dz, zdd) - residual(model, s, z, zd - dz, zdd)) / h;
  }
  std::vector<std::string> out;
  for (const auto& [m, name] : {std::pair<const Eigen::MatrixXd*, const char*>{&M, "M'"},
                                {&K, "K"},
                                {&C, "C"},
                                {&K_cd, "K (differences)"},
                                {&C_cd, "C (differences)"}}) {
    const auto more = outside(*m, name, pattern);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

TEST(MechanicalCoupling, EveryNonzeroOfRandomTreesWithASpringLiesInsideThePattern) {
  int missed_without_group = 0;
  for (unsigned seed = 1; seed <= 30; ++seed) {
    Rng rng(seed);
    const Model model = random_tree(rng, 5, 14);
    const int nb = model.num_bodies();
    Spring s;
    s.a = BodyPoint{rng.integer(0, nb - 1), rng.vector(-1.0, 1.0)};
    s.b = BodyPoint{rng.integer(kGround, nb - 1), rng.vector(-1.0, 1.0)};
    s.k = rng.uniform(10.0, 100.0);
    s.c = rng.uniform(1.0, 10.0);
    const std::vector<std::vector<int>> groups = {coordinates_moving(model, {s.a.body, s.b.body})};
    Rng values(seed + 1000);
    const auto bad = nonzeros_outside(model, s, groups, values);
    EXPECT_TRUE(bad.empty()) << "seed " << seed << ": " << bad.size() << " nonzeros outside, e.g. "
                             << bad.front();
    // Without the spring's group the same check must see its coupling
    // whenever the spring joins two branches neither of which holds the other.
    Rng again(seed + 1000);
    if (!nonzeros_outside(model, s, {}, again).empty()) ++missed_without_group;
  }
  EXPECT_GT(missed_without_group, 5) << "the check never fails: it would not see a missing entry";
}

TEST(MechanicalCoupling, ACutJointCouplesTheCoordinatesThatMoveItsBodies) {
  Model model;
  for (int j = 0; j < 5; ++j) {
    Body body;
    body.name = "b" + std::to_string(j);
    body.coordinate = "z" + std::to_string(j);
    body.parent = j < 2 ? kGround : j - 2;  // two branches: 0-2-4 and 1-3
    model.bodies.push_back(body);
  }
  CutJoint joint;
  joint.a.body = 4;
  joint.b.body = 3;
  model.cut_joints.push_back(joint);
  const auto entries = mechanical_coupling(model, {});
  const std::set<std::pair<int, int>> pattern(entries.begin(), entries.end());
  // The tree alone: 0-2, 0-4, 2-4, 1-3 and the diagonal; the joint joins both branches.
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) EXPECT_EQ(pattern.count({i, j}), 1U) << i << ", " << j;
  model.cut_joints.clear();
  const auto tree = mechanical_coupling(model, {});
  const std::set<std::pair<int, int>> tree_pattern(tree.begin(), tree.end());
  EXPECT_EQ(tree_pattern.size(), 5U + 2U * 4U);
  EXPECT_EQ(tree_pattern.count({0, 1}), 0U);
  EXPECT_EQ(tree_pattern.count({3, 4}), 0U);
}

// Bodies of a beam hinged about z at `at` on `parent`.
std::string beam(const std::string& name, const std::string& parent, double at, double z0) {
  return "  - {name: " + name + ", parent: " + parent + ", joint: {type: revolute, at: [" +
         std::to_string(at) + ", 0, 0], axis: [0, 0, 1]}, mass: 1, shape: {type: beam, " +
         "length: 0.5}, z0: " + std::to_string(z0) + "}\n";
}

// One base and `arms` arms of two beams: 1 + 2 arms bodies, depth 3.
std::string tree_bodies(int arms) {
  std::string text = "units: {length: m, mass: kg, time: s, angle: deg}\nplanar: true\nbodies:\n";
  text += beam("base", "ground", 0.0, 10.0);
  for (int a = 0; a < arms; ++a) {
    const std::string id = std::to_string(a);
    text += beam("a" + id, "base", 0.5, 360.0 * a / arms + 5.0);
    text += beam("c" + id, "a" + id, 0.5, 20.0);
  }
  return text;
}

// Every entry of the run's central-difference tangent that is not zero lies in
// its pattern; and the pattern is sparse.
void expect_tangent_inside_pattern(const std::string& text, const std::string& formulation) {
  const ModelFile file = parse_model_text(text, "generated.yaml");
  Simulation sim(file, test::build_plugins(), RunChoices{formulation, "", {}, {}});
  sim.start();
  for (int k = 0; k < 20; ++k) sim.step();
  const Eigen::MatrixXd J = sim.central_difference_tangent();
  const SparsePattern& p = sim.tangent_pattern();
  const int n = sim.num_unknowns();
  EXPECT_LT(p.nonzeros(), n * n / 2) << formulation << ": the pattern is not sparse";
  int outside_count = 0;
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r)
      if (J(r, c) != 0.0 && p.slot(r, c) < 0) {
        ++outside_count;
        ADD_FAILURE() << formulation << ": d r" << r << " / d x" << c << " = " << J(r, c)
                      << " outside the pattern";
      }
  EXPECT_EQ(outside_count, 0);
  // The analytic tangent holds the same values inside it.
  const Eigen::MatrixXd A = sim.assembled_tangent();
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) {
      const double scale = std::max(1.0, J.row(r).cwiseAbs().maxCoeff());
      EXPECT_NEAR(A(r, c), J(r, c), 1e-5 * scale) << formulation << ": (" << r << ", " << c << ")";
    }
}

TEST(MechanicalCoupling, RunTangentsWithPointForcesAndAStateHaveNoNonzeroOutsideThePattern) {
  // A spring from arm 0's tip to the ground; a Maxwell element (one state)
  // between the tips of arms 1 and 2.
  const std::string subsystems =
      "subsystems:\n"
      "  - {name: s, type: spring-damper, points: {a: {body: c0, at: [0.5, 0, 0]}, b: {body: "
      "ground, at: [1, 1, 0]}}, stiffness: 200, damping: 5, free_length: 0.5}\n"
      "  - {name: m, type: maxwell, points: {a: {body: c1, at: [0.5, 0, 0]}, b: {body: c2, at: "
      "[0.5, 0, 0]}}, states: {delta: delta}, stiffness: 300, damping: 10, free_length: 0.3}\n";
  const std::string solver = "solver: {dt: 0.001, t_end: 1}\n";
  expect_tangent_inside_pattern(tree_bodies(6) + subsystems + "formulation: open-loop\n" + solver,
                                "open-loop");
  // A cut joint joining arms 3 and 4 under penalty.
  const std::string cut =
      "cut_joints:\n  - {name: j, type: revolute, a: {body: c3, at: [0.5, 0, 0]}, b: {body: c4, "
      "at: [0.5, 0, 0]}}\n";
  expect_tangent_inside_pattern(
      tree_bodies(6) + cut + subsystems + "formulation: penalty\n" + solver, "penalty");
}

TEST(MechanicalCoupling, ATreeOfBoundedDepthHasLinearlyManyEntries) {
  // Depth 3: each arm's two coordinates with the base's and each other's.
  for (int arms : {4, 16, 64}) {
    const ModelFile file = parse_model_text(
        tree_bodies(arms) + "formulation: open-loop\n" + "solver: {dt: 0.001, t_end: 1}\n",
        "generated.yaml");
    Simulation sim(file, test::build_plugins(), RunChoices{"open-loop", "", {}, {}});
    EXPECT_EQ(sim.tangent_nonzeros(), 1 + arms * 8) << arms << " arms";
  }
}

// The sparse tangent changes only which entries are stored and KLU's ordering
// (the entries left out are structurally zero): a tree's run with it agrees
// with dense LU on the same equations to round-off, step by step.
TEST(MechanicalCoupling, ATreeRunWithTheSparseTangentMatchesDenseLuToRoundOff) {
  ModelFile file = parse_model_text(
      tree_bodies(8) + "formulation: open-loop\n" + "solver: {dt: 0.001, t_end: 1}\n",
      "generated.yaml");
  Simulation sparse(file, test::build_plugins(), RunChoices{"open-loop", "", {}, {}});
  file.solver.linear = LinearSolverKind::dense;
  Simulation dense(file, test::build_plugins(), RunChoices{"open-loop", "", {}, {}});
  EXPECT_LT(sparse.tangent_nonzeros(), 17 * 17 / 2);
  sparse.start();
  dense.start();
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    sparse.step();
    dense.step();
    worst = std::max(worst, (sparse.z() - dense.z()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(std::abs(sparse.z()[0] - file.model.initial_coordinates()[0]), 1e-3)
      << "the tree did not move: the comparison means nothing";
}

}  // namespace
}  // namespace mh
