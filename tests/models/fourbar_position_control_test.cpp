// models/fourbar-position-control.yaml: the boom's stroke under a PI loop
// closed inside the model. The sensor agrees with the cylinder's own length
// and speed (an independent computation of the same geometry), the loop
// settles within 1e-4 m of its setpoint with both formulations, and the
// tangent with the signal ports (the spool reading the controller, the
// controller reading the sensor, the sensor reading the mechanics) equals
// central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

constexpr double kS0 = 1.4142135623730951;  // m: the sensor's offset, G-F at the start

ModelFile position_control() {
  return load_model_file(test::source_path("models/fourbar-position-control.yaml"));
}

void expect_settles_and_measures(const std::string& formulation) {
  SCOPED_TRACE(formulation);
  const ModelFile file = position_control();
  Simulation sim(file, test::build_plugins(),
                 RunChoices{formulation, "", std::nullopt, std::nullopt});
  sim.start();
  const int stroke = sim.state_index("stroke"), speed = sim.state_index("stroke.v");
  const int s = sim.output_index("s"), sdot = sim.output_index("sdot");
  const int setpoint = sim.input_index("stroke_setpoint");
  ASSERT_GE(stroke, 0);
  ASSERT_GE(speed, 0);
  ASSERT_GE(s, 0);
  ASSERT_GE(setpoint, 0);
  double worst_length = 0.0, worst_speed = 0.0, max_speed = 0.0;
  while (sim.time() < 10.0 - 1e-9) {
    sim.step();
    worst_length = std::max(worst_length, std::abs(sim.states()[stroke] + kS0 - sim.outputs()[s]));
    worst_speed = std::max(worst_speed, std::abs(sim.states()[speed] - sim.outputs()[sdot]));
    max_speed = std::max(max_speed, std::abs(sim.outputs()[sdot]));
  }
  EXPECT_LT(worst_length, 1e-9);
  EXPECT_GT(max_speed, 1e-2);  // the boom did move
  EXPECT_LT(worst_speed, 1e-6 * max_speed);
  // Settled: the last setpoint (10 mm) within 1e-4 m, and still.
  EXPECT_DOUBLE_EQ(sim.input(setpoint), 0.01);
  EXPECT_LT(std::abs(sim.states()[stroke] - 0.01), 1e-4);
  EXPECT_LT(std::abs(sim.outputs()[sdot]), 1e-4);
}

TEST(FourbarPositionControl, SettlesWithin1e4MetresAndTheSensorIsTheCylindersLengthDoubleStep) {
  expect_settles_and_measures("double-step");
}

TEST(FourbarPositionControl, SettlesWithin1e4MetresAndTheSensorIsTheCylindersLengthPenalty) {
  expect_settles_and_measures("penalty");
}

// At t = 1.1 s the valve is open and every signal moves: the spool's row
// depends on the controller's output, the controller's on the sensor's, and
// the sensor's on the coordinates.
TEST(FourbarPositionControl, TangentWithSignalPortsEqualsCentralDifferences) {
  const ModelFile file = position_control();
  Simulation sim(file, test::build_plugins());
  sim.start();
  while (sim.time() < 1.1 - 1e-9) sim.step();
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  const Eigen::Index n_m = sim.num_mechanical_unknowns();
  const int u = sim.state_index("U"), cmd = sim.state_index("U_cmd"),
            stroke = sim.state_index("stroke");
  ASSERT_GE(u, 0);
  ASSERT_GE(cmd, 0);
  // The couplings the ports make are there and analytic.
  EXPECT_NE(J_cd(n_m + u, n_m + cmd), 0.0);
  EXPECT_NE(J_cd(n_m + cmd, n_m + stroke), 0.0);
  for (Eigen::Index r = 0; r < J.rows(); ++r) {
    const double scale = std::max(J_cd.row(r).cwiseAbs().maxCoeff(), 1e-300);
    for (Eigen::Index c = 0; c < J.cols(); ++c)
      EXPECT_NEAR(J(r, c), J_cd(r, c), 1e-5 * scale) << "row " << r << ", column " << c;
  }
}

}  // namespace
}  // namespace mh
