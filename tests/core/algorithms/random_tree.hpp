// Random 3D trees for the core's tests: bodies with random parents, joint
// types, axes, joint points, orientations, masses and physically valid inertias.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <random>
#include <string>

#include "monohydra/core/model.hpp"

namespace mh::test {

struct Rng {
  explicit Rng(unsigned seed) : engine(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine); }
  Eigen::Vector3d vector(double lo, double hi) {
    return Eigen::Vector3d(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi));
  }
  Eigen::Vector3d unit_vector() {
    std::normal_distribution<double> normal;
    Eigen::Vector3d v(normal(engine), normal(engine), normal(engine));
    return v.normalized();
  }
  Eigen::Matrix3d rotation() {
    std::normal_distribution<double> normal;
    Eigen::Quaterniond q(normal(engine), normal(engine), normal(engine), normal(engine));
    return q.normalized().toRotationMatrix();
  }
  // A physically valid inertia about the COM: J = tr(S) I - S for a second
  // moment S = B B^T of some mass distribution (SPD, triangle inequalities hold).
  Eigen::Matrix3d inertia() {
    Eigen::Matrix3d B;
    for (int i = 0; i < 9; ++i) B(i) = uniform(-0.5, 0.5);
    const Eigen::Matrix3d S = B * B.transpose() + 0.01 * Eigen::Matrix3d::Identity();
    return S.trace() * Eigen::Matrix3d::Identity() - S;
  }
  std::mt19937 engine;
};

// min_bodies to max_bodies (>= 3) bodies, parents anywhere earlier (or the ground), a mix of
// revolute and prismatic joints with random axes, joint points, orientations and masses.
inline Model random_tree(Rng& rng, int min_bodies = 4, int max_bodies = 8) {
  Model model;
  model.name = "random";
  const int n = rng.integer(min_bodies, max_bodies);
  for (int j = 0; j < n; ++j) {
    Body body;
    body.name = "b" + std::to_string(j);
    body.coordinate = "z" + std::to_string(j);
    body.parent = rng.integer(kGround, j - 1);
    body.joint = rng.uniform(0.0, 1.0) < 0.5 ? JointType::revolute : JointType::prismatic;
    body.joint_P = rng.vector(-1.0, 1.0);
    body.axis_P = rng.unit_vector();
    body.R_P_B0 = rng.rotation();
    body.mass = rng.uniform(0.5, 3.0);
    body.com_B = rng.vector(-0.5, 0.5);
    body.inertia_B = rng.inertia();
    model.bodies.push_back(body);
  }
  // Both joint types must be present for the test to mean something.
  model.bodies[1].joint = JointType::prismatic;
  model.bodies[2].joint = JointType::revolute;
  model.gravity = 9.81 * rng.unit_vector();
  return model;
}

inline Eigen::VectorXd random_vector(Rng& rng, int n, double lo, double hi) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = rng.uniform(lo, hi);
  return v;
}

}  // namespace mh::test
