// Tests of the analytic derivatives of the open-loop dynamics: K and C against
// central differences of mass_matrix_and_forces (Eq. 12) on random 3D and
// planar trees with spring-dampers and nonlinear point forces, and a pendulum
// whose K and C are known in closed form.
#include "monohydra/core/dynamics_derivatives.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model_file.hpp"
#include "random_tree.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

using test::random_tree;
using test::random_vector;
using test::Rng;

// A linear spring-damper between two body points: F on a is
// (k (L - L0) + c e . (v_b - v_a)) e with e = (p_b - p_a) / L; b gets -F.
struct SpringDamper {
  BodyPoint a, b;
  double k = 0.0, c = 0.0, L0 = 0.0;
};

// A nonlinear force on one point: a position-dependent field plus quadratic drag,
//   F = s (sin p_y, p_x p_z, cos p_x) - cq |v| v.
struct FieldDrag {
  BodyPoint point;
  double s = 0.0, cq = 0.0;
};

struct Loads {
  std::vector<SpringDamper> springs;
  std::vector<FieldDrag> fields;
};

Eigen::Vector3d spring_force(const SpringDamper& sd, const Data& data) {
  const Eigen::Vector3d d = point_position(data, sd.b) - point_position(data, sd.a);
  const Eigen::Vector3d vr = point_velocity(data, sd.b) - point_velocity(data, sd.a);
  const double L = d.norm();
  const Eigen::Vector3d e = d / L;
  return (sd.k * (L - sd.L0) + sd.c * e.dot(vr)) * e;
}

Eigen::Vector3d field_force(const FieldDrag& f, const Data& data) {
  const Eigen::Vector3d p = point_position(data, f.point);
  const Eigen::Vector3d v = point_velocity(data, f.point);
  return f.s * Eigen::Vector3d(std::sin(p.y()), p.x() * p.z(), std::cos(p.x())) -
         f.cq * v.norm() * v;
}

// The loads as point force terms with their exact derivatives.
std::vector<PointForceTerm> force_terms(const Loads& loads, const Data& data) {
  std::vector<PointForceTerm> out;
  for (const SpringDamper& sd : loads.springs) {
    const Eigen::Vector3d d = point_position(data, sd.b) - point_position(data, sd.a);
    const Eigen::Vector3d vr = point_velocity(data, sd.b) - point_velocity(data, sd.a);
    const double L = d.norm();
    const Eigen::Vector3d e = d / L;
    const Eigen::Matrix3d P = (Eigen::Matrix3d::Identity() - e * e.transpose()) / L;  // de/dd
    const double magnitude = sd.k * (L - sd.L0) + sd.c * e.dot(vr);
    const Eigen::Matrix3d dF_dd =
        e * (sd.k * e.transpose() + sd.c * vr.transpose() * P) + magnitude * P;
    const Eigen::Matrix3d dF_dvr = sd.c * e * e.transpose();
    PointForceTerm on_a;  // F(d, vr) with d = p_b - p_a
    on_a.point = sd.a;
    on_a.F_W = magnitude * e;
    on_a.dF_dp = -dF_dd;
    on_a.dF_dv = -dF_dvr;
    on_a.other = sd.b;
    on_a.dF_dp_other = dF_dd;
    on_a.dF_dv_other = dF_dvr;
    PointForceTerm on_b;  // -F
    on_b.point = sd.b;
    on_b.F_W = -on_a.F_W;
    on_b.dF_dp = -dF_dd;
    on_b.dF_dv = -dF_dvr;
    on_b.other = sd.a;
    on_b.dF_dp_other = dF_dd;
    on_b.dF_dv_other = dF_dvr;
    out.push_back(on_a);
    out.push_back(on_b);
  }
  for (const FieldDrag& f : loads.fields) {
    const Eigen::Vector3d p = point_position(data, f.point);
    const Eigen::Vector3d v = point_velocity(data, f.point);
    PointForceTerm t;
    t.point = f.point;
    t.F_W = field_force(f, data);
    t.dF_dp << 0.0, std::cos(p.y()), 0.0, p.z(), 0.0, p.x(), -std::sin(p.x()), 0.0, 0.0;
    t.dF_dp *= f.s;
    const double speed = v.norm();
    t.dF_dv = -f.cq * (speed * Eigen::Matrix3d::Identity() +
                       (speed > 0.0 ? Eigen::Matrix3d(v * v.transpose() / speed)
                                    : Eigen::Matrix3d::Zero()));
    out.push_back(t);
  }
  return out;
}

// M'(z) zdd - Q'(z, zd) from the existing algorithms, loads recomputed at (z, zd).
Eigen::VectorXd residual(const Model& model, const Loads& loads, const Eigen::VectorXd& z,
                         const Eigen::VectorXd& zd, const Eigen::VectorXd& zdd) {
  Data data(model);
  forward_kinematics(model, data, z, zd);
  reset_applied_forces(model, data);
  for (const SpringDamper& sd : loads.springs) {
    const Eigen::Vector3d F = spring_force(sd, data);
    apply_point_force(data, sd.a.body, point_position(data, sd.a), F);
    apply_point_force(data, sd.b.body, point_position(data, sd.b), -F);
  }
  for (const FieldDrag& f : loads.fields) {
    apply_point_force(data, f.point.body, point_position(data, f.point), field_force(f, data));
  }
  mass_matrix_and_forces(model, data);
  return data.M * zdd - data.Q;
}

struct Errors {
  double K = 0.0, C = 0.0, residual = 0.0;
};

double relative(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
  return (got - want).cwiseAbs().maxCoeff() / std::max(want.cwiseAbs().maxCoeff(), 1e-300);
}

// K and C against central differences of residual(); returns the relative errors.
Errors compare(const Model& model, const Loads& loads, const Eigen::VectorXd& z,
               const Eigen::VectorXd& zd, const Eigen::VectorXd& zdd) {
  const int N = model.num_coordinates();
  Data data(model);
  forward_kinematics(model, data, z, zd);
  DynamicsDerivativesWorkspace ws(model);
  Eigen::MatrixXd K(N, N), C(N, N);
  dynamics_derivatives(model, data, zdd, force_terms(loads, data), ws, K, C);

  const double h = 1e-6;
  Eigen::MatrixXd K_fd(N, N), C_fd(N, N);
  for (int k = 0; k < N; ++k) {
    Eigen::VectorXd dz = Eigen::VectorXd::Zero(N);
    dz[k] = h;
    K_fd.col(k) =
        (residual(model, loads, z + dz, zd, zdd) - residual(model, loads, z - dz, zd, zdd)) /
        (2.0 * h);
    C_fd.col(k) =
        (residual(model, loads, z, zd + dz, zdd) - residual(model, loads, z, zd - dz, zdd)) /
        (2.0 * h);
  }
  Errors e;
  e.K = relative(K, K_fd);
  e.C = relative(C, C_fd);
  e.residual = relative(ws.residual, residual(model, loads, z, zd, zdd));
  return e;
}

BodyPoint random_point(Rng& rng, int bodies, bool allow_ground) {
  return BodyPoint{rng.integer(allow_ground ? kGround : 0, bodies - 1), rng.vector(-1.0, 1.0)};
}

// Two spring-dampers (one may end on the ground) and one nonlinear point force.
Loads random_loads(Rng& rng, int bodies) {
  Loads loads;
  for (int s = 0; s < 2; ++s) {
    SpringDamper sd;
    sd.a = random_point(rng, bodies, false);
    sd.b = random_point(rng, bodies, s == 1);
    sd.k = rng.uniform(10.0, 100.0);
    sd.c = rng.uniform(1.0, 10.0);
    sd.L0 = rng.uniform(0.1, 1.0);
    loads.springs.push_back(sd);
  }
  FieldDrag f;
  f.point = random_point(rng, bodies, false);
  f.s = rng.uniform(5.0, 20.0);
  f.cq = rng.uniform(0.5, 2.0);
  loads.fields.push_back(f);
  return loads;
}

// A random tree that moves in the XY plane: revolute axes Z, prismatic axes,
// joint points and centres of mass in the plane, orientations about Z.
Model random_planar_tree(Rng& rng) {
  Model model = random_tree(rng, 3, 10);
  model.planar = true;
  for (Body& body : model.bodies) {
    body.joint_P.z() = 0.0;
    body.com_B.z() = 0.0;
    if (body.joint == JointType::revolute) {
      body.axis_P = Eigen::Vector3d::UnitZ();
    } else {
      body.axis_P =
          Eigen::Vector3d(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.0).normalized();
    }
    body.R_P_B0 =
        Eigen::AngleAxisd(rng.uniform(-3.0, 3.0), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  model.gravity = Eigen::Vector3d(rng.uniform(-1.0, 1.0), -9.81, 0.0);
  return model;
}

Loads planar_loads(Rng& rng, int bodies) {
  Loads loads = random_loads(rng, bodies);
  for (SpringDamper& sd : loads.springs) {
    sd.a.p_B.z() = 0.0;
    sd.b.p_B.z() = 0.0;
  }
  loads.fields.clear();  // the field pushes out of the plane
  return loads;
}

void run_trials(Rng& rng, int trials, bool planar, const char* label) {
  Errors worst;
  for (int trial = 0; trial < trials; ++trial) {
    const Model model = planar ? random_planar_tree(rng) : random_tree(rng, 3, 10);
    const int N = model.num_coordinates();
    const Loads loads = planar ? planar_loads(rng, N) : random_loads(rng, N);
    const Eigen::VectorXd z = random_vector(rng, N, -3.0, 3.0);
    const Eigen::VectorXd zd = random_vector(rng, N, -2.0, 2.0);
    const Eigen::VectorXd zdd = random_vector(rng, N, -3.0, 3.0);
    const Errors e = compare(model, loads, z, zd, zdd);
    EXPECT_LT(e.K, 1e-6) << "trial " << trial << ", " << N << " bodies";
    EXPECT_LT(e.C, 1e-6) << "trial " << trial << ", " << N << " bodies";
    EXPECT_LT(e.residual, 1e-12) << "trial " << trial;
    worst.K = std::max(worst.K, e.K);
    worst.C = std::max(worst.C, e.C);
  }
  std::printf("[ measured ] %s: max relative error K %.2e, C %.2e\n", label, worst.K, worst.C);
}

TEST(DynamicsDerivatives, StiffnessAndDampingMatchCentralDifferencesOnRandom3DTrees) {
  Rng rng(2021);
  run_trials(rng, 40, false, "random 3D trees");
}

TEST(DynamicsDerivatives, StiffnessAndDampingMatchCentralDifferencesOnRandomPlanarTrees) {
  Rng rng(7);
  run_trials(rng, 20, true, "random planar trees");
}

// Chains of 34-40 random joints (mean depth above 6) take the factored fill.
TEST(DynamicsDerivatives, FactoredFillOnDeepChainsMatchesCentralDifferences) {
  Rng rng(64);
  Errors worst;
  for (int trial = 0; trial < 4; ++trial) {
    Model model = random_tree(rng, 34, 40);
    for (int j = 0; j < model.num_bodies(); ++j) model.bodies[j].parent = j - 1;
    ASSERT_TRUE(DynamicsDerivativesWorkspace(model).use_factored_fill);
    const int N = model.num_coordinates();
    const Loads loads = random_loads(rng, N);
    const Errors e = compare(model, loads, random_vector(rng, N, -3.0, 3.0),
                             random_vector(rng, N, -2.0, 2.0), random_vector(rng, N, -3.0, 3.0));
    EXPECT_LT(e.K, 1e-6) << "trial " << trial << ", " << N << " bodies";
    EXPECT_LT(e.C, 1e-6) << "trial " << trial << ", " << N << " bodies";
    EXPECT_LT(e.residual, 1e-12) << "trial " << trial;
    worst.K = std::max(worst.K, e.K);
    worst.C = std::max(worst.C, e.C);
  }
  std::printf("[ measured ] deep chains (factored fill): max relative error K %.2e, C %.2e\n",
              worst.K, worst.C);
}

// The random trees above (at most 10 bodies: mean depth at most 5.5) take the
// subtree sweep.
TEST(DynamicsDerivatives, ShallowTreesTakeTheSubtreeSweep) {
  Rng rng(5);
  EXPECT_FALSE(DynamicsDerivativesWorkspace(random_tree(rng, 3, 10)).use_factored_fill);
}

TEST(DynamicsDerivatives, StiffnessAndDampingMatchCentralDifferencesOnTheCaseStudyModels) {
  for (const char* name : {"models/double-pendulum.yaml", "models/fourbar-free.yaml",
                           "models/quickreturn-free.yaml", "models/crank-rocker.yaml"}) {
    SCOPED_TRACE(name);
    const ModelFile f = load_model_file(test::source_path(name));
    const int N = f.model.num_coordinates();
    Rng rng(3);
    const Loads loads = planar_loads(rng, N);
    const Eigen::VectorXd z = f.model.initial_coordinates() + random_vector(rng, N, -0.3, 0.3);
    const Errors e = compare(f.model, loads, z, random_vector(rng, N, -2.0, 2.0),
                             random_vector(rng, N, -3.0, 3.0));
    EXPECT_LT(e.K, 1e-6);
    EXPECT_LT(e.C, 1e-6);
  }
}

TEST(DynamicsDerivatives, ResidualEqualsMassMatrixTimesAccelerationsMinusForces) {
  Rng rng(99);
  for (int trial = 0; trial < 10; ++trial) {
    const Model model = random_tree(rng, 3, 12);
    const int N = model.num_coordinates();
    const Loads loads = random_loads(rng, N);
    const Eigen::VectorXd z = random_vector(rng, N, -3.0, 3.0);
    const Eigen::VectorXd zd = random_vector(rng, N, -2.0, 2.0);
    const Eigen::VectorXd zdd = random_vector(rng, N, -3.0, 3.0);
    Data data(model);
    forward_kinematics(model, data, z, zd);
    DynamicsDerivativesWorkspace ws(model);
    Eigen::MatrixXd K(N, N), C(N, N);
    dynamics_derivatives(model, data, zdd, force_terms(loads, data), ws, K, C);
    EXPECT_LT(relative(ws.residual, residual(model, loads, z, zd, zdd)), 1e-12);
  }
}

// A pendulum about Z (axis off the world origin), COM at l on the body's X axis,
// with a viscous damper F = -c v at a point lp along the same axis:
//   M' zdd - Q' = (I + m l^2) zdd + m g l cos z + c lp^2 zd
// so K = -m g l sin z and C = c lp^2, whatever zdd and zd.
TEST(DynamicsDerivatives, PendulumWithDamperMatchesClosedForm) {
  const double l = 0.65, lp = 1.1, m = 2.1, g = 9.81, c = 3.7;
  Model model;
  Body rod;
  rod.joint = JointType::revolute;
  rod.joint_P = Eigen::Vector3d(0.4, -0.7, 0.25);
  rod.axis_P = Eigen::Vector3d::UnitZ();
  rod.mass = m;
  rod.com_B = Eigen::Vector3d(l, 0.0, 0.0);
  rod.inertia_B = Eigen::Vector3d(0.01, 0.2, 0.3).asDiagonal();
  model.bodies.push_back(rod);
  model.gravity = Eigen::Vector3d(0.0, -g, 0.0);
  Data data(model);
  DynamicsDerivativesWorkspace ws(model);
  Eigen::MatrixXd K(1, 1), C(1, 1);
  const BodyPoint tip{0, Eigen::Vector3d(lp, 0.0, 0.0)};
  for (double z : {0.0, 0.3, -1.2, 2.5}) {
    for (double zd : {0.0, 1.7, -3.0}) {
      forward_kinematics(model, data, Eigen::VectorXd::Constant(1, z),
                         Eigen::VectorXd::Constant(1, zd));
      PointForceTerm damper;
      damper.point = tip;
      damper.F_W = -c * point_velocity(data, tip);
      damper.dF_dv = -c * Eigen::Matrix3d::Identity();
      dynamics_derivatives(model, data, Eigen::VectorXd::Constant(1, 0.8), {damper}, ws, K, C);
      EXPECT_NEAR(K(0, 0), -m * g * l * std::sin(z), 1e-12) << z << " " << zd;
      EXPECT_NEAR(C(0, 0), c * lp * lp, 1e-12) << z << " " << zd;
      const double inertia = 0.3 + m * l * l;
      EXPECT_NEAR(ws.residual[0], inertia * 0.8 + m * g * l * std::cos(z) + c * lp * lp * zd,
                  1e-12);
    }
  }
}

TEST(DynamicsDerivatives, WrongSizesThrowInvalidArgument) {
  Rng rng(1);
  const Model model = random_tree(rng, 4, 4);
  Data data(model);
  forward_kinematics(model, data, Eigen::VectorXd::Zero(4), Eigen::VectorXd::Zero(4));
  DynamicsDerivativesWorkspace ws(model);
  Eigen::MatrixXd K(4, 4), C(4, 4), wrong(3, 4);
  EXPECT_THROW(dynamics_derivatives(model, data, Eigen::VectorXd::Zero(3), {}, ws, K, C),
               std::invalid_argument);
  EXPECT_THROW(dynamics_derivatives(model, data, Eigen::VectorXd::Zero(4), {}, ws, wrong, C),
               std::invalid_argument);
  EXPECT_NO_THROW(dynamics_derivatives(model, data, Eigen::VectorXd::Zero(4), {}, ws, K, C));
}

}  // namespace
}  // namespace mh
