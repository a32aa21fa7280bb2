// ISO 6015's rated tool forces by virtual work (tool_forces.hpp).
#include "monohydra/core/tool_forces.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "monohydra/core/constraints.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

namespace {

// The loops closed at z (the `fixed` coordinates held) by Gauss-Newton with
// the minimum-norm increment, as the run's initial assembly closes them;
// false when |Phi| does not reach 1e-12 within 50 iterations.
struct LoopCloser {
  const Model& model;
  Data data;
  Constraints constraints;
  std::vector<int> free;
  Eigen::VectorXd phi, phi_dot_zd, zd;
  Eigen::MatrixXd phi_z, a;

  LoopCloser(const Model& m, const std::vector<int>& fixed)
      : model(m), data(m), zd(Eigen::VectorXd::Zero(m.num_coordinates())) {
    forward_kinematics(model, data, model.initial_coordinates(), zd);
    constraints = build_constraints(model, data);
    const int n = model.num_coordinates(), rows = constraints.size();
    for (int j = 0; j < n; ++j)
      if (std::find(fixed.begin(), fixed.end(), j) == fixed.end()) free.push_back(j);
    phi.setZero(rows);
    phi_dot_zd.setZero(rows);
    phi_z.setZero(rows, n);
    a.setZero(rows, static_cast<Eigen::Index>(free.size()));
  }

  bool close(Eigen::VectorXd& z) {
    for (int iteration = 0; iteration < 50; ++iteration) {
      forward_kinematics(model, data, z, zd);
      if (constraints.size() == 0) return true;
      evaluate_constraints(model, data, constraints, phi, phi_z, phi_dot_zd);
      if (phi.lpNorm<Eigen::Infinity>() <= 1e-12) return true;
      if (free.empty()) return false;
      for (size_t c = 0; c < free.size(); ++c)
        a.col(static_cast<Eigen::Index>(c)) = phi_z.col(free[c]);
      const Eigen::VectorXd dz = a.completeOrthogonalDecomposition().solve(-phi);
      for (size_t c = 0; c < free.size(); ++c) z[free[c]] += dz[static_cast<Eigen::Index>(c)];
    }
    return false;
  }
};

double cylinder_length(const Data& data, const ToolForceSpec& spec) {
  return (point_position(data, spec.cylinder_b) - point_position(data, spec.cylinder_a)).norm();
}

// The lip's distance from the joint's axis at the kinematics in `data`.
double lip_radius(const Model& model, const Data& data, const ToolForceSpec& spec) {
  const Body& body = model.bodies[static_cast<size_t>(spec.coordinate)];
  const Eigen::Vector3d axis =
      body.parent == kGround
          ? body.axis_P
          : Eigen::Vector3d(data.R_W_B[static_cast<size_t>(body.parent)] * body.axis_P);
  const Eigen::Vector3d arm =
      point_position(data, spec.lip) - data.o_W[static_cast<size_t>(spec.coordinate)];
  return (arm - arm.dot(axis) * axis).norm();
}

}  // namespace

ToolForce tool_force(const Model& model, const ToolForceSpec& spec) {
  const int n = model.num_coordinates();
  if (spec.coordinate < 0 || spec.coordinate >= n ||
      model.bodies[static_cast<size_t>(spec.coordinate)].joint != JointType::revolute)
    throw std::invalid_argument("the joint a tool force is taken about must be a revolute joint");
  if (!(spec.area > 0.0) || !(spec.pressure > 0.0) || !(spec.step > 0.0) ||
      !(spec.length_max > spec.length_min))
    throw std::invalid_argument(
        "a tool force needs a positive area, pressure and step and a stroke with max > min");
  std::vector<int> fixed = model.assembly_fixed;  // and the joint itself, set at each angle
  fixed.push_back(spec.coordinate);
  LoopCloser closer(model, fixed);
  Eigen::VectorXd z = model.initial_coordinates();
  if (!closer.close(z))
    throw std::invalid_argument("the loops do not close at the model's initial coordinates");
  const Eigen::VectorXd z_initial = z;

  // The force at the angle in z[coordinate], from the loops closed at it
  // and at +-1e-6 rad; false out of the stroke or where they do not close.
  const double h = 1e-6;
  Eigen::VectorXd zq;
  const auto evaluate = [&](Eigen::VectorXd& at, ToolForcePoint& p) {
    if (!closer.close(at)) return false;
    p.angle = at[spec.coordinate];
    p.length = cylinder_length(closer.data, spec);
    p.radius = lip_radius(model, closer.data, spec);
    if (p.length < spec.length_min || p.length > spec.length_max || !(p.radius > 0.0)) return false;
    double ends[2];
    for (int side = 0; side < 2; ++side) {
      zq = at;
      zq[spec.coordinate] += side == 0 ? h : -h;
      if (!closer.close(zq)) return false;
      ends[side] = cylinder_length(closer.data, spec);
    }
    p.lever = (ends[0] - ends[1]) / (2.0 * h);
    p.force = spec.pressure * spec.area * std::abs(p.lever) / p.radius;
    return true;
  };

  ToolForce out;
  z = z_initial;
  if (!evaluate(z, out.initial))
    throw std::invalid_argument(
        "at the model's own pose the cylinder is out of its stroke (or the loops do not close "
        "about the joint)");
  std::vector<ToolForcePoint> below;
  for (const double direction : {1.0, -1.0}) {
    z = z_initial;
    for (int k = 1; k < 4 * 360; ++k) {
      z[spec.coordinate] = z_initial[spec.coordinate] + direction * k * spec.step;
      ToolForcePoint p;
      // Beyond a dead point (dL/dtheta through zero: the cylinder's line
      // through the pivot, or the linkage's turning point) the cylinder no
      // longer turns the joint the same way: the range it drives from the
      // model's pose ends there.
      if (!evaluate(z, p) || !(p.lever * out.initial.lever > 0.0)) break;
      (direction > 0.0 ? out.samples : below).push_back(p);
    }
  }
  std::reverse(below.begin(), below.end());
  below.push_back(out.initial);
  out.samples.insert(out.samples.begin(), below.begin(), below.end());
  out.largest = *std::max_element(
      out.samples.begin(), out.samples.end(),
      [](const ToolForcePoint& a, const ToolForcePoint& b) { return a.force < b.force; });
  return out;
}

}  // namespace mh
