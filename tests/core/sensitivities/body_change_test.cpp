// A body moved along a parameter's direction (core/src/sensitivities/
// body_change.cpp): along a load's direction about the body's origin, by
// the load's mass, it is the loaded body the model file's parser makes (a
// second computation: the parser moves both inertias to the pair's centre
// of mass); along a mass's direction, the plain sums.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

Body bucket_with(double payload) {
  std::ifstream in(test::source_path("models/excavator.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string from = "payload: {mass: 0,";
  const size_t at = yaml.find(from);
  if (at == std::string::npos) throw std::logic_error("models/excavator.yaml has no empty payload");
  yaml.replace(at, from.size(), "payload: {mass: " + std::to_string(payload) + ",");
  const ModelFile file = parse_model_text(yaml, "excavator.yaml", test::source_path("models"));
  for (const Body& b : file.model.bodies)
    if (b.name == "bucket") return b;
  throw std::logic_error("no bucket");
}

Eigen::Matrix3d point(double m, const Eigen::Vector3d& d) {
  return m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

TEST(BodyChange, ALoadMovedAboutTheOriginByItsMassIsTheLoadedBodyTheParserMakes) {
  const Body empty = bucket_with(0.0);
  const Body loaded = bucket_with(1800.0);
  // The excavator's soil: its centre and a box of 1.0 x 1.1 x 0.6 m.
  const Eigen::Vector3d centre(0.80, 0.0, -0.13);
  const Eigen::Vector3d d2 = Eigen::Vector3d(1.0, 1.1, 0.6).cwiseAbs2();
  const Eigen::Matrix3d own_per_kg =
      (Eigen::Vector3d(d2.y() + d2.z(), d2.x() + d2.z(), d2.x() + d2.y()) / 12.0).asDiagonal();
  Body moved = empty;
  move_body(moved, {0, 1.0, centre, point(1.0, centre) + own_per_kg, true}, 1800.0);
  EXPECT_NEAR(moved.mass, loaded.mass, 1e-12 * loaded.mass);
  EXPECT_TRUE(moved.com_B.isApprox(loaded.com_B, 1e-13)) << moved.com_B.transpose();
  EXPECT_TRUE(moved.inertia_B.isApprox(loaded.inertia_B, 1e-12)) << moved.inertia_B;
  // Not the centre of mass's own sum: that direction, taken at the empty
  // bucket, overshoots the loaded centre of mass.
  Body linear = empty;
  move_body(linear, {0, 1.0, (centre - empty.com_B) / empty.mass, Eigen::Matrix3d::Zero(), false},
            1800.0);
  EXPECT_GT((linear.com_B - empty.com_B).norm(), 1.5 * (loaded.com_B - empty.com_B).norm());
}

TEST(BodyChange, AMassesDirectionAddsItsChangesToTheMassCentreAndInertia) {
  Body b;
  b.mass = 2.0;
  b.com_B = Eigen::Vector3d(0.5, 0, 0);
  b.inertia_B = Eigen::Vector3d(0.1, 0.2, 0.3).asDiagonal();
  move_body(b, {0, 1.0, Eigen::Vector3d(0, 0.1, 0), Eigen::Matrix3d::Identity(), false}, 0.5);
  EXPECT_EQ(b.mass, 2.5);
  EXPECT_EQ(b.com_B, Eigen::Vector3d(0.5, 0.05, 0));
  EXPECT_TRUE(b.inertia_B.isApprox(Eigen::Vector3d(0.6, 0.7, 0.8).asDiagonal().toDenseMatrix()));
}

}  // namespace
}  // namespace mh
