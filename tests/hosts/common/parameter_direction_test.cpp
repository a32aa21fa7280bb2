// A path as the engine's sensitivities take it (hosts/common/
// parameter_direction.cpp): a beam's mass moves its inertia as the shape
// derives it, gravity's component is a unit vector, an initial angle moves
// its coordinate in radians, and paths the engine
// cannot change in place, or the file does not write, are refused naming
// the path and why.
#include "parameter_direction.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "build_paths.hpp"
#include "monohydra/core/model_text.hpp"

namespace mh::host {
namespace {

const std::string& fourbar_path() {
  static const std::string path = std::string(test::paths::source_dir) + "/models/fourbar.yaml";
  return path;
}

std::string refusal(const std::string& path) {
  const std::string text = read_model_text(fourbar_path());
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  try {
    (void)parameter_direction(text, "fourbar.yaml", ".", file, path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParameterDirection, ABeamsMassMovesItsInertiaAsItsShapeDerivesIt) {
  const std::string text = read_model_text(fourbar_path());
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  const ParameterDirection p =
      parameter_direction(text, "fourbar.yaml", ".", file, "bodies/body3/mass");
  EXPECT_EQ(p.value, 50.0);
  ASSERT_EQ(p.bodies.size(), 1u);
  EXPECT_EQ(p.bodies[0].body, 2);
  EXPECT_NEAR(p.bodies[0].mass, 1.0, 1e-8);
  // A beam of length L: m L^2 / 12 about its transverse axes.
  EXPECT_NEAR(p.bodies[0].inertia(2, 2), 2.0 * 2.0 / 12.0, 1e-7);
  EXPECT_TRUE(p.bodies[0].com.isZero(1e-9));
  EXPECT_TRUE(p.gravity.isZero(0.0));
}

TEST(ParameterDirection, AGravityComponentIsAUnitVector) {
  const std::string text = read_model_text(fourbar_path());
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  const ParameterDirection p = parameter_direction(text, "fourbar.yaml", ".", file, "gravity/1");
  EXPECT_EQ(p.value, -9.81);
  EXPECT_TRUE(p.bodies.empty());
  EXPECT_NEAR(p.gravity.y(), 1.0, 1e-9);
  EXPECT_NEAR(p.gravity.x(), 0.0, 1e-12);
}

// The file writes angles in degrees: a unit change of z0 moves the
// engine's coordinate by pi/180 rad, and nothing else.
TEST(ParameterDirection, AnInitialAngleInDegreesMovesItsCoordinateInRadians) {
  const std::string text = read_model_text(fourbar_path());
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  const ParameterDirection p =
      parameter_direction(text, "fourbar.yaml", ".", file, "bodies/body2/z0");
  EXPECT_EQ(p.value, -135.0);
  ASSERT_EQ(p.initial.size(), 1u);
  EXPECT_EQ(p.initial[0].coordinate, 1);
  EXPECT_NEAR(p.initial[0].z0, 3.14159265358979 / 180.0, 1e-9);
  EXPECT_EQ(p.initial[0].zd0, 0.0);
  EXPECT_TRUE(p.bodies.empty());
  EXPECT_TRUE(p.gravity.isZero(0.0));
}

TEST(ParameterDirection, AComponentsOptionIsNamedByItsInstanceAndKeyInSI) {
  const std::string text = read_model_text(fourbar_path());
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  const ParameterDirection p =
      parameter_direction(text, "fourbar.yaml", ".", file, "subsystems/V1/bulk_modulus");
  EXPECT_EQ(p.value, 550e6);
  EXPECT_EQ(p.subsystem, "V1");
  EXPECT_EQ(p.key, "bulk_modulus");
  EXPECT_EQ(p.option, 1.0);
  EXPECT_TRUE(p.bodies.empty());
}

// An entry of a component's table option: keyed by the option, its row and
// its column, as the component declares it (a table valve's flows).
TEST(ParameterDirection, AnEntryOfAComponentsTableIsKeyedByTheOptionItsRowAndColumn) {
  std::string text = read_model_text(fourbar_path());
  const std::string from = "flow_coefficient: 2.138e-8";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(),
               "flow_table: [[5, 1e6, 1.069e-4], [10, 1e6, 2.138e-4]]");
  text.replace(text.find("type: valve-4-3"), 15, "type: valve-table");
  const ModelFile file = parse_model_text(text, "fourbar.yaml", ".");
  const ParameterDirection p =
      parameter_direction(text, "fourbar.yaml", ".", file, "subsystems/valve/flow_table/1/2");
  EXPECT_EQ(p.value, 2.138e-4);
  EXPECT_EQ(p.subsystem, "valve");
  EXPECT_EQ(p.key, "flow_table/1/2");
  EXPECT_EQ(p.option, 1.0);
}

// A body's load (payload: mass 0 in the excavator): one-sided (0 kg is a
// bound), in the body's linear parameters about its origin, where a load
// is exactly linear: a unit mass at its centre with the box's inertia.
TEST(ParameterDirection, ALoadsMassMovesTheBodysFirstMomentAndInertiaAboutItsOrigin) {
  const std::string file_path = std::string(test::paths::source_dir) + "/models/excavator.yaml";
  const std::string text = read_model_text(file_path);
  const ModelFile file = parse_model_text(text, "excavator.yaml", ".");
  const ParameterDirection p =
      parameter_direction(text, "excavator.yaml", ".", file, "bodies/bucket/payload/mass");
  EXPECT_EQ(p.value, 0.0);
  ASSERT_EQ(p.bodies.size(), 1u);
  const ParameterDirection::BodyChange& c = p.bodies[0];
  EXPECT_TRUE(c.about_origin);
  EXPECT_EQ(file.model.bodies[static_cast<size_t>(c.body)].name, "bucket");
  EXPECT_NEAR(c.mass, 1.0, 1e-9);
  const Eigen::Vector3d centre(0.80, 0.0, -0.13);
  EXPECT_TRUE(c.com.isApprox(centre, 1e-8)) << c.com.transpose();
  const Eigen::Vector3d d2 = Eigen::Vector3d(1.0, 1.1, 0.6).cwiseAbs2();
  const Eigen::Matrix3d expected =
      centre.squaredNorm() * Eigen::Matrix3d::Identity() - centre * centre.transpose() +
      Eigen::Matrix3d(
          (Eigen::Vector3d(d2.y() + d2.z(), d2.x() + d2.z(), d2.x() + d2.y()) / 12.0).asDiagonal());
  EXPECT_TRUE(c.inertia.isApprox(expected, 1e-8)) << c.inertia;
}

TEST(ParameterDirection, RefusesWhatTheEngineCannotChangeOrTheFileDoesNotWrite) {
  EXPECT_NE(refusal("solver/dt").find("not a parameter sensitivities take"), std::string::npos);
  EXPECT_NE(refusal("bodies/nobody/mass").find("no item named 'nobody'"), std::string::npos);
  const std::string com = refusal("bodies/body3/com/0");
  EXPECT_NE(com.find("bodies/body3/com/0: "), std::string::npos) << com;
}

}  // namespace
}  // namespace mh::host
