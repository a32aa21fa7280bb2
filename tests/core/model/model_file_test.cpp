// Model files: a valid file yields the right Model; every kind of mistake
// yields an InputError naming the file, line, field and expectation.
#include "monohydra/core/model_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "build_paths.hpp"

namespace mh {
namespace {

constexpr double kPi = 3.14159265358979323846;
const char* const kLabel = "model.yaml";

// One revolute body "b" on the ground (lines 1-5); `rest` starts at line 6.
std::string one_body(const std::string& rest) {
  return "units: {length: m, mass: kg, time: s, angle: rad}\n"  // 1
         "bodies:\n"                                            // 2
         "  - name: b\n"                                        // 3
         "    parent: ground\n"                                 // 4
         "    joint: {type: revolute, axis: [0, 0, 1]}\n"       // 5
         + rest;
}

// A valid body b (lines 1-7); `rest` starts at line 8.
std::string valid_body(const std::string& rest) {
  return one_body(
             "    mass: 2\n"                          // 6
             "    shape: {type: beam, length: 1}\n")  // 7
         + rest;
}

std::optional<InputError> error_of(const std::string& text) {
  try {
    parse_model_text(text, kLabel);
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

// The error is at `line` of the file, names `field` and contains `expectation`.
void expect_error(const std::string& text, int line, const std::string& field,
                  const std::string& expectation) {
  const std::optional<InputError> e = error_of(text);
  ASSERT_TRUE(e.has_value()) << "no error for:\n" << text;
  EXPECT_EQ(e->mark().file, kLabel) << e->what();
  EXPECT_EQ(e->mark().line, line) << e->what();
  EXPECT_EQ(e->field(), field) << e->what();
  EXPECT_NE(std::string(e->what()).find(expectation), std::string::npos)
      << "message: " << e->what() << "\nexpected to contain: " << expectation;
}

void expect_message(const std::string& text, const std::string& message) {
  const std::optional<InputError> e = error_of(text);
  ASSERT_TRUE(e.has_value()) << "no error for:\n" << text;
  EXPECT_EQ(std::string(e->what()), message);
}

// --- valid files -------------------------------------------------------------

TEST(ModelFile, LoadsTheDoublePendulum) {
  const std::string path =
      std::string(mh::test::paths::source_dir) + "/models/double-pendulum.yaml";
  const ModelFile file = load_model_file(path);
  const Model& m = file.model;
  EXPECT_EQ(file.path, path);
  EXPECT_EQ(m.name, "double-pendulum");
  ASSERT_EQ(m.num_bodies(), 2);
  EXPECT_EQ(m.bodies[0].name, "link1");
  EXPECT_EQ(m.bodies[1].name, "link2");
  EXPECT_EQ(m.bodies[0].coordinate, "z1");
  EXPECT_EQ(m.bodies[1].coordinate, "z2");
  EXPECT_EQ(m.bodies[0].parent, kGround);
  EXPECT_EQ(m.bodies[1].parent, 0);
  for (const Body& b : m.bodies) {
    EXPECT_EQ(b.joint, JointType::revolute);
    EXPECT_TRUE(b.axis_P.isApprox(Eigen::Vector3d::UnitZ()));
    EXPECT_DOUBLE_EQ(b.mass, 1.0);
    EXPECT_TRUE(b.com_B.isApprox(Eigen::Vector3d(0.5, 0, 0)));
    const Eigen::Matrix3d inertia = Eigen::Vector3d(0.0, 1.0 / 12.0, 1.0 / 12.0).asDiagonal();
    EXPECT_TRUE(b.inertia_B.isApprox(inertia)) << b.inertia_B;
    EXPECT_TRUE(b.R_P_B0.isApprox(Eigen::Matrix3d::Identity()));
    EXPECT_DOUBLE_EQ(b.z0, 0.0);
    EXPECT_DOUBLE_EQ(b.zd0, 0.0);
  }
  EXPECT_TRUE(m.bodies[0].joint_P.isApprox(Eigen::Vector3d::Zero()));
  EXPECT_TRUE(m.bodies[1].joint_P.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(m.gravity.isApprox(Eigen::Vector3d(0, -9.81, 0)));
  EXPECT_TRUE(m.cut_joints.empty());
  EXPECT_TRUE(file.subsystems.empty());
  EXPECT_EQ(file.formulation.name, "open-loop");
  EXPECT_DOUBLE_EQ(file.solver.dt, 0.001);
  EXPECT_DOUBLE_EQ(file.solver.t_end, 10.0);
  ASSERT_EQ(file.body_marks.size(), 2u);
  EXPECT_EQ(file.body_marks[0].file, path);
  EXPECT_GT(file.body_marks[1].line, file.body_marks[0].line);
}

TEST(ModelFile, ConvertsDegreesToRadiansForAnglesOnly) {
  const ModelFile file = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: deg}
bodies:
  - name: arm
    parent: ground
    joint: {type: revolute, at: [0, 1, 0], axis: [0, 0, 2]}
    orientation: {axis: [0, 0, 1], angle: 90}
    mass: 1
    shape: {type: beam, length: 2}
    z0: 90
    zd0: -180
  - name: slider
    parent: arm
    joint: {type: prismatic, at: [2, 0, 0], axis: [1, 0, 0]}
    mass: 0.5
    com: [0, 0, 0]
    inertia: [0, 0, 0]
    z0: 0.25
    zd0: 1.5
)",
                                          kLabel);
  const Body& arm = file.model.bodies[0];
  EXPECT_NEAR(arm.z0, kPi / 2, 1e-15);
  EXPECT_NEAR(arm.zd0, -kPi, 1e-15);
  EXPECT_TRUE(arm.axis_P.isApprox(Eigen::Vector3d::UnitZ()));  // normalized
  EXPECT_TRUE(arm.joint_P.isApprox(Eigen::Vector3d(0, 1, 0)));
  Eigen::Matrix3d rz90;
  rz90 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_TRUE(arm.R_P_B0.isApprox(rz90, 1e-12)) << arm.R_P_B0;
  const Body& slider = file.model.bodies[1];
  EXPECT_EQ(slider.joint, JointType::prismatic);
  EXPECT_DOUBLE_EQ(slider.z0, 0.25);  // metres are never converted
  EXPECT_DOUBLE_EQ(slider.zd0, 1.5);
  EXPECT_TRUE(slider.inertia_B.isZero());
}

TEST(ModelFile, RadiansAreKept) {
  const ModelFile file = parse_model_text(valid_body("    z0: 1.5\n    zd0: -0.5\n"), kLabel);
  EXPECT_DOUBLE_EQ(file.model.bodies[0].z0, 1.5);
  EXPECT_DOUBLE_EQ(file.model.bodies[0].zd0, -0.5);
}

TEST(ModelFile, BeamAndCuboidShapes) {
  const ModelFile file = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: rad}
bodies:
  - name: beam
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 3
    shape: {type: beam, length: 2}
  - name: box
    parent: ground
    joint: {type: prismatic, axis: [1, 0, 0]}
    mass: 3
    shape: {type: cuboid, length: 2}
  - name: beam-with-com
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 3
    shape: {type: beam, length: 2}
    com: [0.2, 0.1, 0]
  - name: beam-with-inertia
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 3
    shape: {type: beam, length: 2}
    inertia: [1, 2, 3]
)",
                                          kLabel);
  const auto& bodies = file.model.bodies;
  ASSERT_EQ(bodies.size(), 4u);
  // Beam: m L^2 / 12 = 3 * 4 / 12 = 1 about the transverse axes, 0 along it.
  EXPECT_TRUE(bodies[0].com_B.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(bodies[0].inertia_B.isApprox(Eigen::Matrix3d(Eigen::Vector3d(0, 1, 1).asDiagonal())))
      << bodies[0].inertia_B;
  // Cube: m L^2 / 6 = 2 about each axis through its centre.
  EXPECT_TRUE(bodies[1].com_B.isZero());
  EXPECT_TRUE(bodies[1].inertia_B.isApprox(2.0 * Eigen::Matrix3d::Identity()))
      << bodies[1].inertia_B;
  // Explicit com / inertia override the shape's.
  EXPECT_TRUE(bodies[2].com_B.isApprox(Eigen::Vector3d(0.2, 0.1, 0)));
  EXPECT_TRUE(bodies[2].inertia_B.isApprox(Eigen::Matrix3d(Eigen::Vector3d(0, 1, 1).asDiagonal())));
  EXPECT_TRUE(bodies[3].com_B.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_TRUE(bodies[3].inertia_B.isApprox(Eigen::Matrix3d(Eigen::Vector3d(1, 2, 3).asDiagonal())));
}

// The inertia about the centre of mass of a uniform solid of mass m, by
// midpoint quadrature over cells: `inside` says whether a point is in it,
// [lo, hi] bounds it. An independent check of the closed forms.
Eigen::Matrix3d integrated_inertia(double m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                   const std::function<bool(const Eigen::Vector3d&)>& inside,
                                   Eigen::Vector3d& com) {
  const int n = 60;
  const Eigen::Vector3d h = (hi - lo) / n;
  std::vector<Eigen::Vector3d> cells;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d p = lo + h.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        if (inside(p)) cells.push_back(p);
      }
  const double dm = m / static_cast<double>(cells.size());
  com.setZero();
  for (const auto& p : cells) com += p / static_cast<double>(cells.size());
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  for (const auto& p : cells) {
    const Eigen::Vector3d r = p - com;
    J += dm * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return J;
}

TEST(ModelFile, BoxAndCylinderShapesHaveTheInertiaOfUniformSolids) {
  const ModelFile file = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: rad}
bodies:
  - name: box
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 6
    shape: {type: box, size: [3, 2, 1], at: [0.5, -0.25, 0.1]}
  - name: drum
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 4
    shape: {type: cylinder, length: 2, radius: 0.3}
  - name: drawn-only
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 4
    shape: {type: cylinder, length: 2, radius: 0.3}
    com: [0.4, 0, 0]
    inertia: [1, 2, 3]
)",
                                          kLabel);
  const auto& bodies = file.model.bodies;
  ASSERT_EQ(bodies.size(), 3u);
  ASSERT_EQ(file.body_shapes.size(), 3u);
  // Box: centred on `at`, m (b^2 + c^2) / 12 about x and so on.
  Eigen::Vector3d com;
  const Eigen::Vector3d at(0.5, -0.25, 0.1), half(1.5, 1.0, 0.5);
  const Eigen::Matrix3d box = integrated_inertia(
      6, at - half, at + half, [](const Eigen::Vector3d&) { return true; }, com);
  EXPECT_TRUE(bodies[0].com_B.isApprox(at));
  EXPECT_LT((com - at).norm(), 1e-9);
  EXPECT_TRUE(bodies[0].inertia_B.isApprox(box, 1e-3)) << bodies[0].inertia_B << "\n" << box;
  EXPECT_TRUE(bodies[0].inertia_B.isApprox(
      Eigen::Matrix3d(Eigen::Vector3d(2.5, 5.0, 6.5).asDiagonal())));  // 6/12 (5, 10, 13)
  EXPECT_EQ(file.body_shapes[0].kind, BodyShape::Kind::box);
  EXPECT_TRUE(file.body_shapes[0].size.isApprox(Eigen::Vector3d(3, 2, 1)));
  EXPECT_TRUE(file.body_shapes[0].at.isApprox(at));
  // Cylinder: from the joint point along x, m r^2 / 2 about its axis and
  // m (3 r^2 + L^2) / 12 across.
  const Eigen::Matrix3d drum = integrated_inertia(
      4, Eigen::Vector3d(0, -0.3, -0.3), Eigen::Vector3d(2, 0.3, 0.3),
      [](const Eigen::Vector3d& p) { return p.y() * p.y() + p.z() * p.z() <= 0.09; }, com);
  EXPECT_TRUE(bodies[1].com_B.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_LT((com - Eigen::Vector3d(1, 0, 0)).norm(), 1e-9);
  EXPECT_TRUE(bodies[1].inertia_B.isApprox(drum, 5e-3)) << bodies[1].inertia_B << "\n" << drum;
  EXPECT_EQ(file.body_shapes[1].kind, BodyShape::Kind::cylinder);
  EXPECT_TRUE(file.body_shapes[1].size.isApprox(Eigen::Vector3d(2, 0.3, 0.3)));
  // Given com and inertia win: the shape is then only what is drawn.
  EXPECT_TRUE(bodies[2].com_B.isApprox(Eigen::Vector3d(0.4, 0, 0)));
  EXPECT_TRUE(bodies[2].inertia_B.isApprox(Eigen::Matrix3d(Eigen::Vector3d(1, 2, 3).asDiagonal())));
  EXPECT_EQ(file.body_shapes[2].kind, BodyShape::Kind::cylinder);
}

// A load the body carries (payload:): the body becomes the pair, its mass,
// centre of mass and inertia about it; here checked through the inertia
// about the body's origin, a second way. None (mass 0) leaves the body as
// written, to the bit.
TEST(ModelFile, APayloadMakesTheBodyTheLoadedPairAndNoneLeavesItAsWritten) {
  const ModelFile loaded = parse_model_text(
      valid_body("    payload: {mass: 3, at: [1, 0.2, 0], size: [0.2, 0.4, 0.6]}\n"), kLabel);
  const ModelFile empty = parse_model_text(valid_body(""), kLabel);
  const ModelFile none =
      parse_model_text(valid_body("    payload: {mass: 0, at: [1, 0.2, 0]}\n"), kLabel);
  const Body& b = loaded.model.bodies[0];
  const Body& e = empty.model.bodies[0];
  const auto point = [](double m, const Eigen::Vector3d& d) {
    return Eigen::Matrix3d(m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Vector3d at(1, 0.2, 0);
  const Eigen::Matrix3d own =
      Eigen::Vector3d(3.0 / 12 * (0.16 + 0.36), 3.0 / 12 * (0.04 + 0.36), 3.0 / 12 * (0.04 + 0.16))
          .asDiagonal();
  EXPECT_EQ(b.mass, 5.0);
  EXPECT_TRUE(b.com_B.isApprox((2.0 * e.com_B + 3.0 * at) / 5.0, 1e-15)) << b.com_B.transpose();
  const Eigen::Matrix3d about_origin = e.inertia_B + point(2.0, e.com_B) + own + point(3.0, at);
  EXPECT_TRUE((b.inertia_B + point(5.0, b.com_B)).isApprox(about_origin, 1e-14)) << b.inertia_B;
  const Body& n = none.model.bodies[0];
  EXPECT_EQ(n.mass, e.mass);
  EXPECT_EQ(n.com_B, e.com_B);
  EXPECT_EQ(n.inertia_B, e.inertia_B);
}

TEST(ModelFileErrors, APayloadNeedsANonNegativeMassAndItsCentre) {
  expect_error(valid_body("    payload: {mass: -1, at: [0, 0, 0]}\n"), 8, "bodies[0].payload.mass",
               "");
  expect_error(valid_body("    payload: {mass: 1}\n"), 8, "bodies[0].payload.at", "required");
  expect_error(valid_body("    payload: {mass: 1, at: [0, 0, 0], size: [1, 0, 1]}\n"), 8,
               "bodies[0].payload.size", "expected three positive sides");
  expect_error(valid_body("    payload: {mass: 1, at: [0, 0, 0], com: [0, 0, 0]}\n"), 8,
               "bodies[0].payload.com", "unknown key 'com' (expected one of: mass, at, size)");
}

TEST(ModelFileErrors, AShapeTakesTheKeysOfItsType) {
  expect_error(one_body("    mass: 1\n    shape: {type: box, size: [1, 2, 3], length: 1}\n"), 7,
               "bodies[0].shape.length", "unknown key 'length' (expected one of: type, size, at)");
  expect_error(one_body("    mass: 1\n    shape: {type: cylinder, length: 1}\n"), 7,
               "bodies[0].shape.radius", "required");
  expect_error(one_body("    mass: 1\n    shape: {type: box, size: [1, 0, 3]}\n"), 7,
               "bodies[0].shape.size", "expected three positive sides");
  expect_error(one_body("    mass: 1\n    shape: {type: sphere, radius: 1}\n"), 7,
               "bodies[0].shape.type",
               "unknown shape type 'sphere' (expected one of: beam, cuboid, box or cylinder)");
}

TEST(ModelFile, FullInertiaMatrix) {
  const ModelFile file =
      parse_model_text(one_body("    mass: 1\n"
                                "    com: [0, 0, 0]\n"
                                "    inertia: [[2, -0.5, 0], [-0.5, 2, 0], [0, 0, 1]]\n"),
                       kLabel);
  Eigen::Matrix3d expected;
  expected << 2, -0.5, 0, -0.5, 2, 0, 0, 0, 1;
  EXPECT_TRUE(file.model.bodies[0].inertia_B.isApprox(expected));
}

TEST(ModelFile, SortsBodiesTopologicallyAndKeepsCoordinateNames) {
  // File order: c (child of b), a (ground), b (child of a), d (ground).
  const ModelFile file = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: rad}
bodies:
  - name: c
    parent: b
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 1
    shape: {type: beam, length: 1}
  - name: a
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 1
    shape: {type: beam, length: 1}
  - name: b
    parent: a
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 1
    shape: {type: beam, length: 1}
  - name: d
    parent: ground
    joint: {type: revolute, axis: [0, 0, 1]}
    mass: 1
    shape: {type: beam, length: 1}
cut_joints:
  - name: loop
    type: revolute
    a: {body: c, at: [1, 0, 0]}
    b: {body: d, at: [1, 0, 0]}
subsystems:
  - name: spring
    type: spring-damper
    points: {a: {body: ground}, b: {body: b, at: [0.5, 0, 0]}}
)",
                                          kLabel);
  const auto& bodies = file.model.bodies;
  ASSERT_EQ(bodies.size(), 4u);
  // a and d are ready at once (file order a before d); b follows a, c follows b.
  EXPECT_EQ(bodies[0].name, "a");
  EXPECT_EQ(bodies[1].name, "b");
  EXPECT_EQ(bodies[2].name, "c");
  EXPECT_EQ(bodies[3].name, "d");
  EXPECT_EQ(bodies[0].coordinate, "z2");
  EXPECT_EQ(bodies[1].coordinate, "z3");
  EXPECT_EQ(bodies[2].coordinate, "z1");
  EXPECT_EQ(bodies[3].coordinate, "z4");
  EXPECT_EQ(bodies[0].parent, kGround);
  EXPECT_EQ(bodies[1].parent, 0);
  EXPECT_EQ(bodies[2].parent, 1);
  EXPECT_EQ(bodies[3].parent, kGround);
  for (int j = 0; j < file.model.num_bodies(); ++j) EXPECT_LT(bodies[j].parent, j);
  // Marks follow the bodies.
  ASSERT_EQ(file.body_marks.size(), 4u);
  EXPECT_EQ(file.body_marks[0].line, 8);
  EXPECT_EQ(file.body_marks[1].line, 13);
  EXPECT_EQ(file.body_marks[2].line, 3);
  EXPECT_EQ(file.body_marks[3].line, 18);
  // Points refer to the sorted indices.
  ASSERT_EQ(file.model.cut_joints.size(), 1u);
  EXPECT_EQ(file.model.cut_joints[0].a.body, 2);
  EXPECT_EQ(file.model.cut_joints[0].b.body, 3);
  ASSERT_EQ(file.subsystems.size(), 1u);
  EXPECT_EQ(file.subsystems[0].points.at("a").point.body, kGround);
  EXPECT_TRUE(file.subsystems[0].points.at("a").point.p_B.isZero());
  EXPECT_EQ(file.subsystems[0].points.at("b").point.body, 1);
  EXPECT_TRUE(file.subsystems[0].points.at("b").point.p_B.isApprox(Eigen::Vector3d(0.5, 0, 0)));
}

TEST(ModelFile, AlreadySortedFileKeepsItsOrder) {
  const ModelFile file = parse_model_text(R"(units: {length: m, mass: kg, time: s, angle: rad}
bodies:
  - {name: p, parent: ground, joint: {type: revolute}, mass: 1, shape: {type: beam, length: 1}}
  - {name: q, parent: ground, joint: {type: revolute}, mass: 1, shape: {type: beam, length: 1}}
  - {name: r, parent: p, joint: {type: revolute}, mass: 1, shape: {type: beam, length: 1}}
  - {name: s, parent: q, joint: {type: revolute}, mass: 1, shape: {type: beam, length: 1}}
)",
                                          kLabel);
  const auto& bodies = file.model.bodies;
  ASSERT_EQ(bodies.size(), 4u);
  EXPECT_EQ(bodies[0].name, "p");
  EXPECT_EQ(bodies[1].name, "q");
  EXPECT_EQ(bodies[2].name, "r");
  EXPECT_EQ(bodies[3].name, "s");
  EXPECT_EQ(bodies[2].parent, 0);
  EXPECT_EQ(bodies[3].parent, 1);
  EXPECT_EQ(bodies[3].coordinate, "z4");
}

TEST(ModelFile, OptionKinds) {
  const ModelFile file = parse_model_text(valid_body(R"(subsystems:
  - name: valve
    type: proportional-valve
    states: {spool: x_spool, velocity: v_spool}
    k: 1000
    c: -2.5e3
    fluid: "hlp46"
    mode: linear
    quoted_number: "12"
    flow: [1, 2, 3]
    curve: [[0, 0], [1e5, 0.5], [2e5, 1.0]]
)"),
                                          kLabel);
  ASSERT_EQ(file.subsystems.size(), 1u);
  const SubsystemSpec& s = file.subsystems[0];
  EXPECT_EQ(s.name, "valve");
  EXPECT_EQ(s.type, "proportional-valve");
  EXPECT_EQ(s.mark.line, 9);
  EXPECT_EQ(s.state_names.at("spool"), "x_spool");
  EXPECT_EQ(s.state_names.at("velocity"), "v_spool");
  EXPECT_TRUE(s.points.empty());
  EXPECT_EQ(s.options.size(), 7u);
  EXPECT_EQ(s.options.count("name"), 0u);
  EXPECT_EQ(s.options.count("type"), 0u);
  EXPECT_EQ(s.options.count("states"), 0u);

  const OptionValue& k = s.options.at("k");
  EXPECT_EQ(k.kind, OptionValue::Kind::number);
  EXPECT_DOUBLE_EQ(k.number, 1000.0);
  EXPECT_EQ(k.text, "1000");
  EXPECT_EQ(k.mark.file, kLabel);
  EXPECT_EQ(k.mark.line, 12);
  EXPECT_EQ(k.mark.column, 8);
  EXPECT_DOUBLE_EQ(s.options.at("c").number, -2500.0);

  EXPECT_EQ(s.options.at("fluid").kind, OptionValue::Kind::string);
  EXPECT_EQ(s.options.at("fluid").text, "hlp46");
  EXPECT_EQ(s.options.at("mode").kind, OptionValue::Kind::string);
  EXPECT_EQ(s.options.at("mode").text, "linear");
  EXPECT_EQ(s.options.at("quoted_number").kind, OptionValue::Kind::string);
  EXPECT_EQ(s.options.at("quoted_number").text, "12");

  const OptionValue& flow = s.options.at("flow");
  EXPECT_EQ(flow.kind, OptionValue::Kind::table);
  EXPECT_EQ(flow.rows, 1);
  EXPECT_EQ(flow.columns, 3);
  EXPECT_EQ(flow.table, (std::vector<double>{1, 2, 3}));

  const OptionValue& curve = s.options.at("curve");
  EXPECT_EQ(curve.kind, OptionValue::Kind::table);
  EXPECT_EQ(curve.rows, 3);
  EXPECT_EQ(curve.columns, 2);
  EXPECT_EQ(curve.table, (std::vector<double>{0, 0, 1e5, 0.5, 2e5, 1.0}));
}

TEST(ModelFile, FormulationWithOptionsAndSolverSettings) {
  const ModelFile file =
      parse_model_text(valid_body(R"(formulation: {name: penalty, alpha: 1e11, omega: 10}
solver: {dt: 0.0005, t_end: 2, max_iterations: 40, tol_position: 1e-9}
)"),
                       kLabel);
  EXPECT_EQ(file.formulation.name, "penalty");
  EXPECT_EQ(file.formulation.mark.line, 8);
  ASSERT_EQ(file.formulation.options.size(), 2u);
  EXPECT_DOUBLE_EQ(file.formulation.options.at("alpha").number, 1e11);
  EXPECT_DOUBLE_EQ(file.formulation.options.at("omega").number, 10.0);
  EXPECT_DOUBLE_EQ(file.solver.dt, 0.0005);
  EXPECT_DOUBLE_EQ(file.solver.t_end, 2.0);
  EXPECT_EQ(file.solver.max_iterations, 40);
  EXPECT_DOUBLE_EQ(file.solver.tol_position, 1e-9);
  EXPECT_EQ(file.solver.mark.line, 9);
}

TEST(ModelFile, Defaults) {
  const ModelFile file = parse_model_text(valid_body(""), "dir/my-model.yaml");
  EXPECT_EQ(file.path, "dir/my-model.yaml");
  EXPECT_EQ(file.model.name, "my-model");  // the file name without extension
  EXPECT_TRUE(file.model.gravity.isApprox(Eigen::Vector3d(0, -9.81, 0)));
  EXPECT_TRUE(file.model.cut_joints.empty());
  EXPECT_TRUE(file.subsystems.empty());
  EXPECT_TRUE(file.plugin_paths.empty());
  EXPECT_EQ(file.formulation.name, "open-loop");
  EXPECT_TRUE(file.formulation.options.empty());
  EXPECT_DOUBLE_EQ(file.solver.dt, 1e-3);
  EXPECT_DOUBLE_EQ(file.solver.t_end, 10.0);
  EXPECT_EQ(file.solver.max_iterations, 25);
  EXPECT_DOUBLE_EQ(file.solver.tol_position, 1e-7);
  const Body& b = file.model.bodies[0];
  EXPECT_TRUE(b.joint_P.isZero());
  EXPECT_DOUBLE_EQ(b.z0, 0.0);
  EXPECT_DOUBLE_EQ(b.zd0, 0.0);
  EXPECT_TRUE(b.R_P_B0.isApprox(Eigen::Matrix3d::Identity()));
}

TEST(ModelFile, EmptyBodyListIsAllowed) {
  const ModelFile file =
      parse_model_text("units: {length: m, mass: kg, time: s, angle: rad}\nbodies: []\n", kLabel);
  EXPECT_EQ(file.model.num_bodies(), 0);
}

TEST(ModelFile, PluginPathsAreAbsolute) {
  namespace fs = std::filesystem;
  const std::string text = valid_body("plugin_paths: [plugins, ../shared/lib, /opt/mh/plugins]\n");
  const ModelFile file = parse_model_text(text, "m.yaml", "/data/models");
  ASSERT_EQ(file.plugin_paths.size(), 3u);
  EXPECT_EQ(file.plugin_paths[0], "/data/models/plugins");
  EXPECT_EQ(file.plugin_paths[1], "/data/shared/lib");
  EXPECT_EQ(file.plugin_paths[2], "/opt/mh/plugins");

  // Relative to the current folder by default.
  const ModelFile here = parse_model_text(text, "m.yaml");
  EXPECT_TRUE(fs::path(here.plugin_paths[0]).is_absolute());
  EXPECT_EQ(here.plugin_paths[0], (fs::current_path() / "plugins").lexically_normal().string());
}

TEST(ModelFile, PluginsMapsEachIdToAnAbsoluteLibraryFile) {
  const std::string text =
      valid_body("plugins: {penalty: lib/my-penalty.so, spring: /opt/mh/spring.so}\n");
  const ModelFile file = parse_model_text(text, "m.yaml", "/data/models");
  ASSERT_EQ(file.plugin_libraries.size(), 2u);
  EXPECT_EQ(file.plugin_libraries.at("penalty"), "/data/models/lib/my-penalty.so");
  EXPECT_EQ(file.plugin_libraries.at("spring"), "/opt/mh/spring.so");
}

TEST(ModelFileErrors, PluginsMustMapIdsToLibraryFiles) {
  expect_error(valid_body("plugins: [penalty]\n"), 8, "plugins",
               "expected a mapping from component id to library file");
  expect_error(valid_body("plugins: {penalty: \"\"}\n"), 8, "plugins.penalty",
               "expected the path of a plugin library (.so)");
}

TEST(ModelFile, PluginPathsOfALoadedFileAreRelativeToItsFolder) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(mh::test::paths::binary_dir) / "model_file_test";
  fs::create_directories(dir);
  const fs::path path = dir / "with-plugins.yaml";
  {
    std::FILE* f = std::fopen(path.string().c_str(), "w");
    ASSERT_NE(f, nullptr);
    const std::string text = valid_body("plugin_paths: [plugins]\n");
    std::fputs(text.c_str(), f);
    std::fclose(f);
  }
  const ModelFile file = load_model_file(path.string());
  ASSERT_EQ(file.plugin_paths.size(), 1u);
  EXPECT_EQ(file.plugin_paths[0], (fs::absolute(dir) / "plugins").lexically_normal().string());
}

TEST(ModelFile, CutJoints) {
  const ModelFile file = parse_model_text(valid_body(R"(cut_joints:
  - name: E
    type: spherical
    a: {body: b, at: [1, 0, 0]}
    b: {body: ground, at: [0, -1, 0]}
  - name: F
    type: translational
    a: {body: ground}
    b: {body: b}
    axis: [0, 3, 0]
)"),
                                          kLabel);
  const auto& cuts = file.model.cut_joints;
  ASSERT_EQ(cuts.size(), 2u);
  EXPECT_EQ(cuts[0].name, "E");
  EXPECT_EQ(cuts[0].type, CutJointType::spherical);
  EXPECT_EQ(cuts[0].a.body, 0);
  EXPECT_TRUE(cuts[0].a.p_B.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_EQ(cuts[0].b.body, kGround);
  EXPECT_TRUE(cuts[0].b.p_B.isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(cuts[0].axis_a.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(cuts[1].type, CutJointType::translational);
  EXPECT_TRUE(cuts[1].axis_a.isApprox(Eigen::Vector3d::UnitY()));
}

TEST(ModelFile, DocumentationExampleParses) {
  // The first ```yaml block of docs/model-format.md is the complete example.
  std::ifstream in(std::string(mh::test::paths::source_dir) + "/docs/model-format.md");
  ASSERT_TRUE(in) << "docs/model-format.md not found";
  std::string line;
  std::string yaml;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line == "```yaml") {
      inside = true;
    } else if (inside && line == "```") {
      break;
    } else if (inside) {
      yaml += line + "\n";
    }
  }
  ASSERT_FALSE(yaml.empty());
  const ModelFile file = parse_model_text(yaml, "model-format.md", "/base");
  const Model& m = file.model;
  ASSERT_EQ(m.num_bodies(), 3);
  // crank and barrel hang from the ground, piston from barrel (written first).
  EXPECT_EQ(m.bodies[0].name, "crank");
  EXPECT_EQ(m.bodies[1].name, "barrel");
  EXPECT_EQ(m.bodies[2].name, "piston");
  EXPECT_EQ(m.bodies[2].coordinate, "z1");
  EXPECT_EQ(m.bodies[2].parent, 1);
  EXPECT_NEAR(m.bodies[0].z0, kPi / 6, 1e-15);
  EXPECT_DOUBLE_EQ(m.bodies[2].z0, 0.1);
  ASSERT_EQ(m.cut_joints.size(), 1u);
  EXPECT_EQ(m.cut_joints[0].a.body, 2);
  EXPECT_EQ(m.cut_joints[0].b.body, 0);
  ASSERT_EQ(file.subsystems.size(), 2u);
  EXPECT_EQ(file.subsystems[0].options.at("friction_curve").rows, 3);
  EXPECT_EQ(file.subsystems[0].points.at("rod").point.body, 2);
  EXPECT_EQ(file.formulation.name, "penalty");
  EXPECT_EQ(file.plugin_paths, (std::vector<std::string>{"/base/plugins", "/shared/plugins"}));
}

// --- errors ------------------------------------------------------------------

TEST(ModelFileErrors, MalformedYaml) {
  const std::string text =
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies: [\n"
      "  {name: a\n";
  const std::optional<InputError> e = error_of(text);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->mark().file, kLabel);
  EXPECT_GE(e->mark().line, 2);
  EXPECT_NE(std::string(e->what()).find("malformed YAML"), std::string::npos) << e->what();

  expect_error("units: {length: m\nbodies: : :\n", 2, "", "malformed YAML");
  // A tab where indentation is expected.
  const std::optional<InputError> tab = error_of("units:\n\tlength: m\n");
  ASSERT_TRUE(tab.has_value());
  EXPECT_EQ(tab->mark().line, 2) << tab->what();
}

TEST(ModelFileErrors, NotAMapping) {
  expect_error("", 0, "", "expected a mapping with the model");
  expect_error("- 1\n- 2\n", 1, "", "expected a mapping with the model");
}

TEST(ModelFileErrors, MissingUnits) {
  expect_message("bodies: []\n",
                 "model.yaml:1:1: units: missing required key 'units' (write units: {length: m, "
                 "mass: kg, time: s, angle: rad} (or angle: deg))");
  expect_error("units: {length: m, mass: kg, time: s}\nbodies: []\n", 1, "units.angle",
               "missing required key 'angle'");
}

TEST(ModelFileErrors, NonSiUnits) {
  expect_message("units: {length: mm, mass: kg, time: s, angle: rad}\nbodies: []\n",
                 "model.yaml:1:17: units.length: expected 'm' (only SI units are supported; only "
                 "angles may be 'deg'), got 'mm'");
  expect_error("units: {length: m, mass: g, time: s, angle: rad}\nbodies: []\n", 1, "units.mass",
               "expected 'kg'");
  expect_error("units: {length: m, mass: kg, time: ms, angle: rad}\nbodies: []\n", 1, "units.time",
               "expected 's'");
  expect_error("units: {length: m, mass: kg, time: s, angle: grad}\nbodies: []\n", 1, "units.angle",
               "expected 'rad' or 'deg', got 'grad'");
  expect_error("units: {length: m, mass: kg, time: s, angle: rad, force: N}\nbodies: []\n", 1,
               "units.force", "unknown key 'force'");
}

TEST(ModelFileErrors, UnknownTopLevelKey) {
  expect_message(valid_body("solvr: {dt: 0.01}\n"),
                 "model.yaml:8:1: solvr: unknown key 'solvr' (expected one of: units, name, "
                 "gravity, plugin_paths, plugins, bodies, cut_joints, subsystems, formulation, "
                 "integrator, compare, solver, planar, assembly, nodes, equilibrium, output, "
                 "inputs, sensors)");
}

TEST(ModelFileErrors, UnknownBodyKey) {
  expect_message(one_body("    mas: 1\n    shape: {type: beam, length: 1}\n"),
                 "model.yaml:6:5: bodies[0].mas: unknown key 'mas' (expected one of: name, "
                 "parent, joint, orientation, mass, shape, com, inertia, payload, z0, zd0)");
  expect_error(one_body("    mass: 1\n    shape: {type: beam, lenght: 1}\n"), 7,
               "bodies[0].shape.lenght", "unknown key 'lenght' (expected one of: type, length)");
  expect_error(valid_body("solver: {dt: 0.01, tend: 1}\n"), 8, "solver.tend", "unknown key 'tend'");
}

TEST(ModelFileErrors, DuplicateKey) {
  expect_error(one_body("    mass: 1\n    mass: 2\n    shape: {type: beam, length: 1}\n"), 7,
               "bodies[0].mass", "duplicate key 'mass' (first written at line 6)");
}

TEST(ModelFileErrors, MissingRequiredBodyKeys) {
  expect_error(one_body("    shape: {type: beam, length: 1}\n"), 3, "bodies[0].mass",
               "missing required key 'mass'");
  expect_error(one_body("    mass: 1\n    inertia: [1, 1, 1]\n"), 3, "bodies[0].com",
               "missing required key 'com' (required when no shape is given)");
  expect_error(one_body("    mass: 1\n    com: [0, 0, 0]\n"), 3, "bodies[0].inertia",
               "missing required key 'inertia'");
  expect_error(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - {name: a, joint: {type: revolute}, mass: 1, shape: {type: beam, length: 1}}\n",
      3, "bodies[0].parent", "missing required key 'parent'");
  // Neither bodies nor subsystems: nothing to simulate (either alone is a model).
  expect_error("units: {length: m, mass: kg, time: s, angle: rad}\n", 1, "bodies",
               "expected bodies: (a list of bodies, may be empty) or subsystems: (a model of "
               "subsystems only), found neither");
}

TEST(ModelFileErrors, UnknownJointType) {
  expect_message(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - name: b\n"
      "    parent: ground\n"
      "    joint: {type: hinge, axis: [0, 0, 1]}\n"
      "    mass: 1\n"
      "    shape: {type: beam, length: 1}\n",
      "model.yaml:5:19: bodies[0].joint.type: unknown joint type 'hinge' (expected one of: "
      "revolute, prismatic)");
  expect_error(valid_body("cut_joints:\n  - {name: c, type: ball, a: {body: b}, b: {body: "
                          "ground}}\n"),
               9, "cut_joints[0].type", "unknown cut joint type 'ball'");
  expect_error(one_body("    mass: 1\n    shape: {type: disc, length: 1}\n"), 7,
               "bodies[0].shape.type", "unknown shape type 'disc'");
}

TEST(ModelFileErrors, BadMass) {
  const std::string shape = "    shape: {type: beam, length: 1}\n";
  expect_message(one_body("    mass: nan\n" + shape),
                 "model.yaml:6:11: bodies[0].mass: expected a positive finite number, got 'nan'");
  expect_error(one_body("    mass: .nan\n" + shape), 6, "bodies[0].mass",
               "expected a positive finite number, got '.nan'");
  expect_error(one_body("    mass: -1\n" + shape), 6, "bodies[0].mass",
               "expected a positive finite number, got '-1'");
  expect_error(one_body("    mass: 0\n" + shape), 6, "bodies[0].mass",
               "expected a positive finite number, got '0'");
  expect_error(one_body("    mass: .inf\n" + shape), 6, "bodies[0].mass",
               "expected a positive finite number, got '.inf'");
  expect_error(one_body("    mass:\n" + shape), 6, "bodies[0].mass",
               "expected a positive finite number, got nothing");
}

TEST(ModelFileErrors, BadInertia) {
  const std::string head = "    mass: 1\n    com: [0, 0, 0]\n";  // lines 6-7
  expect_message(one_body(head + "    inertia: [1, -0.5, 1]\n"),
                 "model.yaml:8:18: bodies[0].inertia[1]: expected a non-negative finite number, "
                 "got '-0.5'");
  expect_error(one_body(head + "    inertia: [1, 1, nan]\n"), 8, "bodies[0].inertia[2]",
               "expected a non-negative finite number, got 'nan'");
  expect_error(one_body(head + "    inertia: [[1, 0, 0], [0, 1, .nan], [0, 0, 1]]\n"), 8,
               "bodies[0].inertia[1][2]", "expected a finite number, got '.nan'");
  expect_error(one_body(head + "    inertia: [[1, 0.1, 0], [0.2, 1, 0], [0, 0, 1]]\n"), 8,
               "bodies[0].inertia", "expected a symmetric matrix");
  expect_error(one_body(head + "    inertia: [[1, 2, 0], [2, 1, 0], [0, 0, 1]]\n"), 8,
               "bodies[0].inertia", "expected a positive semidefinite matrix");
  expect_error(one_body(head + "    inertia: [[1, 0, 0], [0, 1, 0]]\n"), 8, "bodies[0].inertia",
               "or a 3x3 nested list, got a list of 2 items");
  expect_error(one_body(head + "    inertia: [[1, 0, 0], [0, 1], [0, 0, 1]]\n"), 8,
               "bodies[0].inertia[1]", "expected a row of 3 numbers, got a list of 2 items");
}

TEST(ModelFileErrors, ZeroAxis) {
  expect_message(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - name: b\n"
      "    parent: ground\n"
      "    joint: {type: revolute, axis: [0, 0, 0]}\n"
      "    mass: 1\n"
      "    shape: {type: beam, length: 1}\n",
      "model.yaml:5:35: bodies[0].joint.axis: expected a non-zero axis, got [0, 0, 0]");
  expect_error(valid_body("    orientation: {axis: [0, 0, 0], angle: 1}\n"), 8,
               "bodies[0].orientation.axis", "expected a non-zero axis");
  expect_error(valid_body("cut_joints:\n  - {name: c, type: revolute, a: {body: b}, b: {body: "
                          "ground}, axis: [0, 0, 0]}\n"),
               9, "cut_joints[0].axis", "expected a non-zero axis");
}

TEST(ModelFileErrors, UnknownParent) {
  expect_message(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - {name: a, parent: ground, joint: {type: revolute}, mass: 1, shape: {type: beam, "
      "length: 1}}\n"
      "  - {name: b, parent: lnk1, joint: {type: revolute}, mass: 1, shape: {type: beam, "
      "length: 1}}\n",
      "model.yaml:4:23: bodies[1].parent: unknown parent body 'lnk1' (expected one of: ground, "
      "a)");
}

TEST(ModelFileErrors, CycleNamesTheBodies) {
  expect_message(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - {name: root, parent: ground, joint: {type: revolute}, mass: 1, shape: {type: beam, "
      "length: 1}}\n"
      "  - {name: x, parent: z, joint: {type: revolute}, mass: 1, shape: {type: beam, length: "
      "1}}\n"
      "  - {name: tail, parent: x, joint: {type: revolute}, mass: 1, shape: {type: beam, length: "
      "1}}\n"
      "  - {name: y, parent: x, joint: {type: revolute}, mass: 1, shape: {type: beam, length: "
      "1}}\n"
      "  - {name: z, parent: y, joint: {type: revolute}, mass: 1, shape: {type: beam, length: "
      "1}}\n",
      "model.yaml:4:23: bodies[1].parent: the parents form a cycle: x -> z -> y -> x (every "
      "chain of parents must end at 'ground')");
  expect_error(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - {name: self, parent: self, joint: {type: revolute}, mass: 1, shape: {type: beam, "
      "length: 1}}\n",
      3, "bodies[0].parent", "cycle: self -> self");
}

TEST(ModelFileErrors, DuplicateNames) {
  const std::string body =
      "    parent: ground\n"
      "    joint: {type: revolute}\n"
      "    mass: 1\n"
      "    shape: {type: beam, length: 1}\n";
  expect_message(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - name: arm\n" +
          body + "  - name: arm\n" + body,
      "model.yaml:8:11: bodies[1].name: duplicate body name 'arm' (first defined at "
      "line 3, column 5)");
  expect_error(valid_body("subsystems:\n"
                          "  - {name: s, type: spring-damper}\n"
                          "  - {name: s, type: spring-damper}\n"),
               10, "subsystems[1].name", "duplicate subsystem name 's'");
  expect_error(valid_body("cut_joints:\n"
                          "  - {name: c, type: spherical, a: {body: b}, b: {body: ground}}\n"
                          "  - {name: c, type: spherical, a: {body: b}, b: {body: ground}}\n"),
               10, "cut_joints[1].name", "duplicate cut joint name 'c'");
  expect_error(
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "bodies:\n"
      "  - name: ground\n" +
          body,
      3, "bodies[0].name", "'ground' is reserved");
  expect_error(valid_body("subsystems:\n"
                          "  - {name: s1, type: t, states: {x: pos}}\n"
                          "  - {name: s2, type: t, states: {y: pos}}\n"),
               10, "subsystems[1].states.y", "duplicate result column name 'pos'");
}

TEST(ModelFileErrors, PointOnUnknownBody) {
  expect_message(valid_body("subsystems:\n"
                            "  - name: spring\n"
                            "    type: spring-damper\n"
                            "    points: {a: {body: ground}, b: {body: bb, at: [1, 0, 0]}}\n"),
                 "model.yaml:11:43: subsystems[0].points.b.body: unknown body 'bb' (expected "
                 "one of: ground, b)");
  expect_error(valid_body("cut_joints:\n  - {name: c, type: spherical, a: {body: nope}, b: "
                          "{body: ground}}\n"),
               9, "cut_joints[0].a.body", "unknown body 'nope'");
  expect_error(valid_body("cut_joints:\n  - {name: c, type: spherical, a: {body: b}, b: "
                          "{body: b}}\n"),
               9, "cut_joints[0].b.body", "two different bodies");
}

TEST(ModelFileErrors, WrongVectorLength) {
  expect_message(valid_body("gravity: [0, -9.81]\n"),
                 "model.yaml:8:10: gravity: expected a list of 3 numbers, got a list of 2 items");
  expect_error(one_body("    mass: 1\n    shape: {type: beam, length: 1}\n    com: [0, 0, 0, 0]\n"),
               8, "bodies[0].com", "expected a list of 3 numbers, got a list of 4 items");
  expect_error(valid_body("gravity: 9.81\n"), 8, "gravity",
               "expected a list of 3 numbers, got '9.81'");
}

TEST(ModelFileErrors, NotANumber) {
  expect_message(valid_body("gravity: [0, minus, 0]\n"),
                 "model.yaml:8:14: gravity[1]: expected a finite number, got 'minus'");
  expect_error(one_body("    mass: \"1.0\"\n    shape: {type: beam, length: 1}\n"), 6,
               "bodies[0].mass", "expected a positive finite number, got '1.0'");
  expect_error(one_body("    mass: [1]\n    shape: {type: beam, length: 1}\n"), 6, "bodies[0].mass",
               "expected a positive finite number, got a list of 1 item");
  expect_error(valid_body("    z0: 1deg\n"), 8, "bodies[0].z0",
               "expected a finite number, got '1deg'");
  expect_error(valid_body("subsystems:\n  - {name: s, type: t, curve: [[0, 1], [x, 2]]}\n"), 9,
               "subsystems[0].curve[1][0]", "expected a finite number, got 'x'");
  expect_error(valid_body("subsystems:\n  - {name: s, type: t, curve: [[0, 1], [1, 2, 3]]}\n"), 9,
               "subsystems[0].curve[1]", "expected 2 numbers like the first row");
  expect_error(valid_body("subsystems:\n  - {name: s, type: t, k: {a: 1}}\n"), 9, "subsystems[0].k",
               "expected a number, a string, a list of numbers");
}

TEST(ModelFileErrors, MissingFile) {
  const std::string path = "/nonexistent/monohydra/model.yaml";
  try {
    load_model_file(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.mark().file, path);
    EXPECT_EQ(e.mark().line, 0);
    EXPECT_EQ(std::string(e.what()), path + ": cannot open the model file: no such file");
  }
}

// gravity: [1e300, -9.81, 0] once ran to the end with the bodies frozen
// (found by the mutation run, tests/mutation).
TEST(ModelFileErrors, GravityAboveAThousandGIsRefusedWithTheRange) {
  const std::string text =
      "units: {length: m, mass: kg, time: s, angle: rad}\n"
      "gravity: [1e300, -9.81, 0]\n"
      "bodies:\n"
      "  - {name: rod, parent: ground, joint: {type: revolute}, mass: 1,"
      " shape: {type: beam, length: 1}}\n"
      "solver: {dt: 0.001, t_end: 1}\n";
  try {
    parse_model_text(text, kLabel);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "gravity[0]: expected a magnitude up to 10000 m/s^2, got '1e300'"),
              std::string::npos)
        << e.what();
  }
}

TEST(ModelFileErrors, BadSolverSettings) {
  expect_message(valid_body("solver: {dt: 0}\n"),
                 "model.yaml:8:14: solver.dt: expected a positive finite number, got '0'");
  expect_error(valid_body("solver: {dt: -0.001}\n"), 8, "solver.dt",
               "expected a positive finite number, got '-0.001'");
  expect_error(valid_body("solver: {t_end: -1}\n"), 8, "solver.t_end",
               "expected a non-negative finite number, got '-1'");
  expect_error(valid_body("solver: {max_iterations: 0}\n"), 8, "solver.max_iterations",
               "expected an integer >= 1, got '0'");
  expect_error(valid_body("solver: {max_iterations: 2.5}\n"), 8, "solver.max_iterations",
               "expected an integer >= 1, got '2.5'");
  expect_error(valid_body("solver: {tol_position: 0}\n"), 8, "solver.tol_position",
               "expected a positive finite number");
  expect_error(valid_body("solver: {max_step_halvings: -1}\n"), 8, "solver.max_step_halvings",
               "expected an integer >= 0, got '-1'");
  expect_error(valid_body("solver: {max_step_halvings: 11}\n"), 8, "solver.max_step_halvings",
               "expected an integer from 0 to 10");
  EXPECT_EQ(parse_model_text(valid_body("solver: {max_step_halvings: 3}\n"), kLabel)
                .solver.max_step_halvings,
            3);
  EXPECT_EQ(parse_model_text(valid_body(""), kLabel).solver.max_step_halvings, 0);  // default
  // t_end = 0 reads (the initial state alone); a run refuses it (run_limits_test.cpp).
  EXPECT_DOUBLE_EQ(parse_model_text(valid_body("solver: {t_end: 0}\n"), kLabel).solver.t_end, 0.0);
}

TEST(ModelFileErrors, LinearSolverAndNewtonChoicesAreNamedOrRefusedWithTheChoices) {
  expect_error(valid_body("solver: {linear: lapack}\n"), 8, "solver.linear",
               "expected one of: klu, umfpack, dense, auto (the tangent's linear solver; auto: "
               "dense LU for a dense tangent, KLU otherwise), got 'lapack'");
  expect_error(valid_body("solver: {linear: [klu]}\n"), 8, "solver.linear", "expected a string");
  expect_error(valid_body("solver: {newton: quasi}\n"), 8, "solver.newton",
               "expected auto, full, per-step, modified or articulated");
  const ModelFile defaults = parse_model_text(valid_body(""), kLabel);
  EXPECT_EQ(defaults.solver.linear, LinearSolverKind::klu);
  EXPECT_EQ(defaults.solver.newton, NewtonKind::automatic);
  for (LinearSolverKind kind : {LinearSolverKind::klu, LinearSolverKind::umfpack,
                                LinearSolverKind::dense, LinearSolverKind::automatic}) {
    const ModelFile f = parse_model_text(
        valid_body("solver: {linear: " + std::string(to_string(kind)) + "}\n"), kLabel);
    EXPECT_EQ(f.solver.linear, kind) << to_string(kind);
  }
  for (NewtonKind kind : {NewtonKind::full, NewtonKind::per_step, NewtonKind::modified,
                          NewtonKind::articulated, NewtonKind::automatic}) {
    const ModelFile f = parse_model_text(
        valid_body("solver: {newton: " + std::string(to_string(kind)) + "}\n"), kLabel);
    EXPECT_EQ(f.solver.newton, kind) << to_string(kind);
  }
}

TEST(ModelFileErrors, LineSearchIsOffByDefaultOnWhenAskedWithFullNewtonAndRefusedWithAnyOther) {
  EXPECT_FALSE(parse_model_text(valid_body(""), kLabel).solver.line_search);
  EXPECT_TRUE(
      parse_model_text(valid_body("solver: {line_search: on}\n"), kLabel).solver.line_search);
  EXPECT_FALSE(
      parse_model_text(valid_body("solver: {line_search: off}\n"), kLabel).solver.line_search);
  expect_error(valid_body("solver: {line_search: yes}\n"), 8, "solver.line_search",
               "expected on or off");
  expect_error(valid_body("solver: {newton: modified, line_search: on}\n"), 8, "solver.line_search",
               "expected off with newton: modified");
  expect_error(valid_body("solver: {newton: per-step, line_search: on}\n"), 8, "solver.line_search",
               "expected off with newton: per-step");
  // Without a newton key, line_search: on makes full Newton the default,
  // whichever order the keys come in.
  for (const char* body :
       {"solver: {line_search: on}\n", "solver: {line_search: on, newton: full}\n",
        "solver: {newton: full, line_search: on}\n"})
    EXPECT_EQ(parse_model_text(valid_body(body), kLabel).solver.newton, NewtonKind::full) << body;
}

TEST(ModelFileErrors, OutputSettingsAreReadOrRefusedAtTheirLine) {
  const ModelFile f =
      parse_model_text(valid_body("output: {interval: 0.01, columns: [t, z1, KE]}\n"), kLabel);
  EXPECT_DOUBLE_EQ(f.output.interval, 0.01);
  EXPECT_EQ(f.output.columns, (std::vector<std::string>{"t", "z1", "KE"}));
  EXPECT_EQ(f.output.column_marks.at(2).line, 8);
  EXPECT_EQ(parse_model_text(valid_body(""), kLabel).output.interval, 0.0);  // every step
  expect_error(valid_body("output: {interval: 0}\n"), 8, "output.interval",
               "expected a positive finite number, got '0'");
  expect_error(valid_body("output: {columns: []}\n"), 8, "output.columns",
               "expected a non-empty list of result column names");
  expect_error(valid_body("output: {columns: [t, t]}\n"), 8, "output.columns[1]",
               "duplicate column name 't'");
  expect_error(valid_body("output: {every: 2}\n"), 8, "output.every", "unknown key");
}

TEST(ModelFileErrors, WrongShapes) {
  expect_error(valid_body("bodies2: 1\n"), 8, "bodies2", "unknown key");
  expect_error("units: {length: m, mass: kg, time: s, angle: rad}\nbodies: {a: 1}\n", 2, "bodies",
               "expected a list of bodies, got a mapping");
  expect_error(valid_body("formulation: [a]\n"), 8, "formulation",
               "expected a formulation name or a mapping");
  expect_error(valid_body("formulation: {alpha: 1}\n"), 8, "formulation.name",
               "missing required key 'name'");
  expect_error(valid_body("plugin_paths: plugins\n"), 8, "plugin_paths",
               "expected a list of folders");
  expect_error(valid_body("subsystems:\n  - {name: s}\n"), 9, "subsystems[0].type",
               "missing required key 'type'");
  expect_error(valid_body("subsystems:\n  - {name: s, type: t, states: {x: 'a b'}}\n"), 9,
               "subsystems[0].states.x", "without commas, quotes or spaces");
  expect_error(valid_body("---\nunits: {}\n"), 9, "", "expected a single YAML document");
}

}  // namespace
}  // namespace mh

// --- circuits: ports, nodes, equilibrium -------------------------------------

namespace mh {
namespace {

const std::string kCircuitHead =
    "units: {length: m, mass: kg, time: s, angle: deg}\n"  // 1
    "bodies: []\n"                                         // 2
    "subsystems:\n"                                        // 3
    "  - name: orifice\n"                                  // 4
    "    type: throttle\n";                                // 5

TEST(ModelFileCircuits, PortsNodesAndEquilibriumAreRead) {
  const ModelFile f = parse_model_text(kCircuitHead +
                                           "    ports: {a: supply, b: n1}\n"
                                           "nodes: {supply: null, n1: p1}\n"
                                           "equilibrium: {free: [p1]}\n",
                                       kLabel);
  ASSERT_EQ(f.subsystems.size(), 1u);
  EXPECT_EQ(f.subsystems[0].ports.at("a").node, "supply");
  EXPECT_EQ(f.subsystems[0].ports.at("b").node, "n1");
  EXPECT_EQ(f.subsystems[0].ports.at("b").mark.line, 6);
  EXPECT_EQ(f.node_columns.at("supply"), "");
  EXPECT_EQ(f.node_columns.at("n1"), "p1");
  ASSERT_EQ(f.equilibrium_free.size(), 1u);
  EXPECT_EQ(f.equilibrium_free[0], "p1");
}

TEST(ModelFileCircuits, APortJoinsExactlyOneNode) {
  expect_error(kCircuitHead + "    ports: {a: [n1, n2], b: n1}\n", 6, "subsystems[0].ports.a",
               "expected one node name");
}

TEST(ModelFileCircuits, NodesMustBeNamedByAPort) {
  expect_error(kCircuitHead + "    ports: {a: n1, b: n2}\nnodes: {n3: p3}\n", 7, "nodes.n3",
               "unknown node 'n3'");
}

TEST(ModelFileCircuits, NodeColumnsAreUniqueAmongResultColumns) {
  expect_error(
      kCircuitHead + "    ports: {a: n1, b: n2}\n    outputs: {q: flow}\nnodes: {n1: flow}\n", 8,
      "nodes.n1", "duplicate result column");
}

TEST(ModelFileCircuits, ANodeNamedAfterAColumnEveryRunWritesIsRefusedUnlessRenamed) {
  expect_error(kCircuitHead + "    ports: {a: t, b: n2}\n", 6, "subsystems[0].ports.a",
               "a node name that is not a result column every run has, got 't' (a column every "
               "run writes)");
  expect_error(kCircuitHead + "    ports: {a: n1, b: KE}\nnodes: {KE: null}\n", 6,
               "subsystems[0].ports.b", "got 'KE'");
  // Renamed under nodes:, its column is the new name: accepted.
  const ModelFile f =
      parse_model_text(kCircuitHead + "    ports: {a: t, b: n2}\nnodes: {t: p_t}\n", kLabel);
  EXPECT_EQ(f.node_columns.at("t"), "p_t");
}

TEST(ModelFileCircuits, EquilibriumNeedsAListOfStates) {
  expect_error(kCircuitHead + "    ports: {a: n1, b: n2}\nequilibrium: {free: p1}\n", 7,
               "equilibrium.free", "expected a non-empty list");
}

// --- magnitudes, result columns, files that are not models -------------------

TEST(ModelFileLimits, MassAboveOneTeraKilogramIsRefusedWithTheRange) {
  expect_message(
      one_body("    mass: 1e13\n    shape: {type: beam, length: 1}\n"),
      "model.yaml:6:11: bodies[0].mass: expected a magnitude up to 1e+12 kg, got '1e13'");
}

TEST(ModelFileLimits, InertiaAboveTheLimitIsRefused) {
  expect_message(one_body("    mass: 1\n    com: [0, 0, 0]\n    inertia: [1, 1e300, 1]\n"),
                 "model.yaml:8:18: bodies[0].inertia[1]: expected a magnitude up to 1e+12 kg m^2, "
                 "got '1e300'");
}

TEST(ModelFileLimits, LengthsAboveAThousandKilometresAreRefused) {
  expect_message(one_body("    mass: 1\n    shape: {type: beam, length: 2e6}\n"),
                 "model.yaml:7:33: bodies[0].shape.length: expected a magnitude up to 1e+06 m, got "
                 "'2e6'");
  expect_error(valid_body("cut_joints:\n  - {name: c, type: spherical, a: {body: b, at: [0, -1e7, "
                          "0]}, b: {body: ground}}\n"),
               9, "cut_joints[0].a.at[1]", "expected a magnitude up to 1e+06 m, got '-1e7'");
}

TEST(ModelFileLimits, StateColumnMayNotTakeACoordinateColumn) {
  expect_message(valid_body("subsystems:\n  - {name: s, type: t, states: {U: z1}}\n"),
                 "model.yaml:9:36: subsystems[0].states.U: 'z1' is the coordinate column of body "
                 "'b'; pick another name");
}

TEST(ModelFileLimits, OutputColumnMayNotTakeAColumnEveryRunWrites) {
  expect_error(valid_body("subsystems:\n  - {name: s, type: t, outputs: {e: KE}}\n"), 9,
               "subsystems[0].outputs.e", "'KE' is a column every run writes; pick another name");
}

std::string load_error(const std::string& path) {
  try {
    load_model_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::filesystem::path scratch_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("monohydra-model-file-test-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ModelFileLimits, DeviceLikeDevZeroIsRefusedBeforeReading) {
  EXPECT_EQ(load_error("/dev/zero"),
            "/dev/zero: cannot read the model file: not a regular file (a device, FIFO or socket)");
}

TEST(ModelFileLimits, FileAbove64MiBIsRefusedBeforeParsing) {
  const auto path = scratch_file("big.yaml", "");
  std::filesystem::resize_file(path, (64u << 20) + 1);  // sparse: no 64 MiB written
  EXPECT_EQ(load_error(path.string()), path.string() +
                                           ": the model file is 67108865 bytes, above the limit "
                                           "of 67108864 bytes (64 MiB)");
  std::filesystem::remove(path);
}

TEST(ModelFileLimits, BinaryFileIsRefusedAsNotText) {
  const auto path = scratch_file("binary.yaml", std::string("units: {}\n\0\x01\n", 13));
  EXPECT_EQ(load_error(path.string()),
            path.string() + ": not a text file: it holds a NUL byte at offset 10");
  std::filesystem::remove(path);
}

TEST(ModelFileLimits, FileCutMidLineIsRefusedAsCutShort) {
  // The double pendulum cut inside its solver line: "t_end: 10" would read as "t_end: 1".
  std::ifstream in(std::string(mh::test::paths::source_dir) + "/models/double-pendulum.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto path = scratch_file("cut.yaml", text.substr(0, text.size() - 3));
  const std::string error = load_error(path.string());
  EXPECT_EQ(error, path.string() +
                       ":25: the file does not end with a line break, so it may have been cut "
                       "short (end its last line with one)");
  std::filesystem::remove(path);
}

TEST(ModelFileLimits, DeeplyNestedInputIsAnErrorNotAStackOverflow) {
  const std::optional<InputError> e = error_of(std::string(200000, '[') + "\n");
  ASSERT_TRUE(e.has_value());
  EXPECT_NE(std::string(e->what()).find("model.yaml:2:1: malformed YAML: "), std::string::npos)
      << e->what();
}

}  // namespace
}  // namespace mh

// --- inputs ------------------------------------------------------------------

namespace mh {
namespace {

TEST(ModelFileInputs, AnInputWithATableStartsAtItsValueAtZero) {
  const ModelFile file = parse_model_text(
      valid_body("inputs:\n"                                                                // 8
                 "  - {name: lever, unit: V, range: [-10, 10], table: [[0, 2], [1, 5]]}\n"  // 9
                 "  - {name: load, unit: N, initial: 300, out_of_range: clamp}\n"),         // 10
      kLabel);
  ASSERT_EQ(file.inputs.size(), 2u);
  EXPECT_EQ(file.inputs[0].name, "lever");
  EXPECT_EQ(file.inputs[0].unit, "V");
  EXPECT_EQ(file.inputs[0].min, -10.0);
  EXPECT_EQ(file.inputs[0].max, 10.0);
  EXPECT_EQ(file.inputs[0].initial, 2.0);
  EXPECT_EQ(file.inputs[0].table, (std::vector<double>{0, 2, 1, 5}));
  EXPECT_FALSE(file.inputs[0].clamp);
  EXPECT_EQ(file.inputs[1].initial, 300.0);
  EXPECT_TRUE(file.inputs[1].clamp);
  EXPECT_GT(file.inputs[1].min, file.inputs[1].max);  // no range declared
}

TEST(ModelFileInputs, EachMistakeNamesItsLineAndField) {
  expect_error(valid_body("inputs: {name: x}\n"), 8, "inputs", "expected a list of inputs");
  expect_error(valid_body("inputs:\n  - {unit: V}\n"), 9, "inputs[0].name",
               "missing required key 'name'");
  expect_error(valid_body("inputs:\n  - {name: a}\n  - {name: a}\n"), 10, "inputs[1].name",
               "duplicate input name 'a'");
  expect_error(valid_body("inputs:\n  - {name: a, range: [5, 1]}\n"), 9, "inputs[0].range",
               "expected min < max, got [5, 1]");
  expect_error(valid_body("inputs:\n  - {name: a, out_of_range: wrap}\n"), 9,
               "inputs[0].out_of_range", "expected refuse or clamp");
  expect_error(valid_body("inputs:\n  - {name: a, initial: 1, table: [[0, 1]]}\n"), 9,
               "inputs[0].initial", "expected initial or table, not both");
  expect_error(valid_body("inputs:\n  - {name: a, table: [[1, 0], [0, 1]]}\n"), 9,
               "inputs[0].table", "row 2 goes back in time");
  expect_error(valid_body("inputs:\n  - {name: a, range: [0, 1], initial: 2}\n"), 9,
               "inputs[0].initial", "expected an initial value within the range [0, 1], got 2");
  expect_error(valid_body("inputs:\n  - {name: a, range: [0, 1], table: [[0, 0], [1, 3]]}\n"), 9,
               "inputs[0].table[1]", "within the range [0, 1] (out_of_range: refuse), got 3");
  expect_error(valid_body("inputs:\n  - {name: a, colour: red}\n"), 9, "inputs[0].colour",
               "unknown key 'colour' (expected one of: name, unit, range, out_of_range, initial, "
               "table)");
}

}  // namespace
}  // namespace mh
