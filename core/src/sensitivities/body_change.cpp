// A body moved along a parameter's direction (sensitivities.hpp): shared by
// the forward sensitivities' differences and the filters' held parameters,
// so that both move a body alike.
#include <Eigen/Core>

#include "monohydra/core/sensitivities.hpp"

namespace mh {

namespace {

// The inertia a mass m at d from a point adds about it (parallel axes).
Eigen::Matrix3d point_inertia(double m, const Eigen::Vector3d& d) {
  return m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

}  // namespace

void move_body(Body& b, const ParameterDirection::BodyChange& change, double amount) {
  if (!change.about_origin) {
    b.mass += amount * change.mass;
    b.com_B += amount * change.com;
    b.inertia_B += amount * change.inertia;
    return;
  }
  const double mass = b.mass + amount * change.mass;
  const Eigen::Vector3d first_moment = b.mass * b.com_B + amount * change.com;
  const Eigen::Matrix3d about_origin =
      b.inertia_B + point_inertia(b.mass, b.com_B) + amount * change.inertia;
  b.mass = mass;
  b.com_B = first_moment / mass;
  b.inertia_B = about_origin - point_inertia(mass, b.com_B);
}

}  // namespace mh
