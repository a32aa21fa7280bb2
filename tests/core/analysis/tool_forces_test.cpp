// ISO 6015's rated tool forces by virtual work (tool_forces.hpp): a bucket on
// an arm, each turned by a cylinder pinned straight to it, against the
// closed form F = p A |dL/dtheta| / r of the triangle's geometry; the
// excavator's bucket through its four-bar linkage, whose dead point ends the
// range the cylinder drives.
#include "monohydra/core/tool_forces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An arm about the ground's -y axis and a bucket at its tip, a cylinder from
// the ground's (0.3, 0, 1.0) to the arm's (0.8, 0, 0.3), the lip at the
// bucket's (1, 0, -0.2).
const char* const kArm = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, -1, 0]},
     mass: 100, com: [1, 0, 0], inertia: [1, 1, 1], z0: 0.2}
  - {name: bucket, parent: arm, joint: {type: revolute, at: [2, 0, 0], axis: [0, -1, 0]},
     mass: 50, com: [0.5, 0, 0], inertia: [1, 1, 1], z0: -0.5}
subsystems:
  - {name: V_a, type: volume, ports: {p: a}, volume: 1e-3, bulk_modulus: 1e9}
  - {name: V_b, type: volume, ports: {p: b}, volume: 1e-3, bulk_modulus: 1e9}
  - {name: arm_cyl, type: cylinder, ports: {A: a, B: b}, piston_diameter: 0.1, rod_diameter: 0.05,
     length: 0.45, points: {a: {body: ground, at: [0.3, 0, 1.0]}, b: {body: arm, at: [0.8, 0, 0.3]}}}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// The cylinder's end on the arm, turned by theta about -y.
Eigen::Vector3d arm_point(double theta) {
  return {0.8 * std::cos(theta) - 0.3 * std::sin(theta), 0.0,
          0.8 * std::sin(theta) + 0.3 * std::cos(theta)};
}

TEST(ToolForce, ACylinderPinnedToTheArmGivesTheTrianglesClosedFormAtEveryAngle) {
  const ModelFile file = parse_model_text(kArm, "arm.yaml");
  ToolForceSpec spec;
  spec.coordinate = 0;
  spec.lip = BodyPoint{1, Eigen::Vector3d(1.0, 0.0, -0.2)};
  spec.cylinder_a = BodyPoint{kGround, Eigen::Vector3d(0.3, 0.0, 1.0)};
  spec.cylinder_b = BodyPoint{0, Eigen::Vector3d(0.8, 0.0, 0.3)};
  spec.area = 0.25 * kPi * 0.01;
  spec.pressure = 30e6;
  spec.length_min = 0.45;
  spec.length_max = 0.9;
  const ToolForce f = tool_force(file.model, spec);
  // The lip's distance from the arm's axis: the bucket's pivot (2, 0, 0)
  // plus its lip turned by -0.5, in the arm's plane.
  const double r = Eigen::Vector2d(2.0 + std::cos(-0.5) * 1.0 - std::sin(-0.5) * -0.2,
                                   std::sin(-0.5) * 1.0 + std::cos(-0.5) * -0.2)
                       .norm();
  const Eigen::Vector3d a(0.3, 0.0, 1.0);
  ASSERT_GT(f.samples.size(), 100u);
  double largest = 0.0;
  for (const ToolForcePoint& p : f.samples) {
    const Eigen::Vector3d d = arm_point(p.angle) - a;
    const Eigen::Vector3d rate(-0.8 * std::sin(p.angle) - 0.3 * std::cos(p.angle), 0.0,
                               0.8 * std::cos(p.angle) - 0.3 * std::sin(p.angle));
    const double lever = d.dot(rate) / d.norm();
    const double force = spec.pressure * spec.area * std::abs(lever) / r;
    EXPECT_NEAR(p.length, d.norm(), 1e-12);
    EXPECT_NEAR(p.radius, r, 1e-12);
    EXPECT_NEAR(p.force, force, 1e-7 * force);
    EXPECT_GE(p.length, spec.length_min);
    EXPECT_LE(p.length, spec.length_max);
    EXPECT_GT(lever * f.initial.lever, 0.0);
    largest = std::max(largest, force);
  }
  EXPECT_NEAR(f.largest.force, largest, 1e-7 * largest);
  EXPECT_NEAR(f.initial.angle, 0.2, 1e-15);
  // The scan ends where it must: one step further is out of the stroke or
  // past the dead point (dL/dtheta = 0: the cylinder's line through the pivot).
  for (const double end :
       {f.samples.front().angle - spec.step, f.samples.back().angle + spec.step}) {
    const Eigen::Vector3d d = arm_point(end) - a;
    const Eigen::Vector3d rate(-0.8 * std::sin(end) - 0.3 * std::cos(end), 0.0,
                               0.8 * std::cos(end) - 0.3 * std::sin(end));
    const bool out = d.norm() < spec.length_min || d.norm() > spec.length_max ||
                     d.dot(rate) * f.initial.lever <= 0.0;
    EXPECT_TRUE(out) << end;
  }
}

// The excavator's bucket through its rocker and link: the loops closed at
// each angle; the range the cylinder drives ends at the linkage's dead point
// (its length least), where the force falls to zero, not at the toggle
// beyond it, where it would grow without bound.
TEST(ToolForce, TheExcavatorsBucketLinkageEndsItsRangeAtTheDeadPoint) {
  const ModelFile file = load_model_file(test::source_path("models/excavator-ls.yaml"));
  ToolForceSpec spec;
  spec.coordinate = 3;  // bucket
  spec.lip = BodyPoint{3, Eigen::Vector3d(1.25, 0.0, -0.58)};
  for (const SubsystemSpec& s : file.subsystems)
    if (s.name == "bucket_cyl") {
      spec.cylinder_a = s.points.at("a").point;
      spec.cylinder_b = s.points.at("b").point;
    }
  spec.area = 0.25 * kPi * 0.12 * 0.12;
  spec.pressure = 32e6;
  spec.length_min = 1.3;
  spec.length_max = 2.6;
  const ToolForce f = tool_force(file.model, spec);
  // Increasing angle: the cylinder shortens to its dead point.
  for (size_t i = 1; i < f.samples.size(); ++i)
    EXPECT_LT(f.samples[i].length, f.samples[i - 1].length) << i;
  EXPECT_LT(std::abs(f.samples.back().lever), 0.05 * std::abs(f.initial.lever));
  EXPECT_GT(f.largest.force, f.initial.force);
  EXPECT_LT(f.largest.force, 2.0 * f.initial.force);
}

// What tool_force refuses, by its message: a joint that is not revolute (a
// slide, or no joint of the model), a stroke with nothing in it.
TEST(ToolForce, APrismaticJointANonexistentOneOrAnEmptyStrokeIsRefused) {
  const auto refusal = [](const ModelFile& file, int coordinate, double length_max) {
    ToolForceSpec spec;
    spec.coordinate = coordinate;
    spec.area = 1.0;
    spec.pressure = 1.0;
    spec.length_max = length_max;
    try {
      (void)tool_force(file.model, spec);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string revolute = "the joint a tool force is taken about must be a revolute joint";
  const ModelFile slide = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: rad}
bodies:
  - {name: slide, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1, com: [0, 0, 0], inertia: [1, 1, 1]}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)",
                                           "slide.yaml");
  EXPECT_EQ(refusal(slide, 0, 1.0), revolute);
  const ModelFile arm = parse_model_text(kArm, "arm.yaml");
  EXPECT_EQ(refusal(arm, 2, 1.0), revolute);
  EXPECT_EQ(refusal(arm, -1, 1.0), revolute);
  EXPECT_EQ(refusal(arm, 0, 0.0),
            "a tool force needs a positive area, pressure and step and a stroke with max > min");
}

}  // namespace
}  // namespace mh
