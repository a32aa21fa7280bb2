// Parameters held in place as offsets (core/src/estimation/held_parameters.cpp):
// what an offset moves, that an offset put back restores the model to the
// bit, that two parameters on one body add, and the refusals.
#include "monohydra/core/held_parameters.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "core/sensitivities/parameter_directions.hpp"
#include "monohydra/core/model_file.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const ModelFile& fourbar() {
  static const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  return file;
}

TEST(HeldParameters, AnOffsetMovesTheModelAndPutBackRestoresItToTheBit) {
  Simulation sim(fourbar(), test::build_plugins());
  sim.start();
  const Body before = sim.model().bodies[2];
  HeldParameters held(sim, {test::mass_direction(sim.model(), 2),
                            test::option_direction(fourbar(), "valve", "flow_coefficient")});
  held.set(Eigen::Vector2d(5.0, 0.1e-8));
  EXPECT_DOUBLE_EQ(sim.model().bodies[2].mass, before.mass + 5.0);
  EXPECT_TRUE(sim.model().bodies[2].inertia_B.isApprox(before.inertia_B * (before.mass + 5.0) /
                                                       before.mass));
  EXPECT_DOUBLE_EQ(sim.component_parameter("valve", "flow_coefficient"), 2.238e-8);
  EXPECT_DOUBLE_EQ(held.values()[0], before.mass + 5.0);
  held.set(Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(sim.model().bodies[2].mass, before.mass);
  EXPECT_EQ(sim.model().bodies[2].inertia_B, before.inertia_B);
  EXPECT_EQ(sim.component_parameter("valve", "flow_coefficient"), 2.138e-8);
}

TEST(HeldParameters, TwoParametersOnOneBodyAdd) {
  Simulation sim(fourbar(), test::build_plugins());
  sim.start();
  const Body before = sim.model().bodies[2];
  ParameterDirection inertia;
  inertia.path = "bodies/body3/inertia/2";
  inertia.value = before.inertia_B(2, 2);
  Eigen::Matrix3d unit = Eigen::Matrix3d::Zero();
  unit(2, 2) = 1.0;
  inertia.bodies.push_back({2, 0.0, Eigen::Vector3d::Zero(), unit});
  HeldParameters held(sim, {test::mass_direction(sim.model(), 2), inertia});
  held.set(Eigen::Vector2d(5.0, 0.25));
  const double expected = before.inertia_B(2, 2) * (before.mass + 5.0) / before.mass + 0.25;
  EXPECT_NEAR(sim.model().bodies[2].inertia_B(2, 2), expected, 1e-12 * expected);
}

TEST(HeldParameters, RefusesAnInitialCoordinateAndAMassAtZeroKeepingTheOffsets) {
  Simulation sim(fourbar(), test::build_plugins());
  sim.start();
  ParameterDirection z0;
  z0.path = "bodies/body1/z0";
  z0.initial.push_back({0, 1.0, 0.0});
  EXPECT_THROW(HeldParameters(sim, {z0}), std::invalid_argument);
  const Body before = sim.model().bodies[2];
  HeldParameters held(sim, {test::mass_direction(sim.model(), 2)});
  held.set(Eigen::VectorXd::Constant(1, 2.0));
  try {
    held.set(Eigen::VectorXd::Constant(1, -before.mass));
    FAIL() << "a mass of 0 taken";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("bodies/body3/mass: body 'body3'"), std::string::npos)
        << err.what();
  }
  EXPECT_EQ(held.offsets()[0], 2.0);
  EXPECT_DOUBLE_EQ(sim.model().bodies[2].mass, before.mass + 2.0);
}

}  // namespace
}  // namespace mh
