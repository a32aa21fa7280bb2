// models/fourbar-position-control.yaml: the boom's stroke under a PI loop
// closed inside the model. The sensor agrees with the cylinder's own length
// and speed (an independent computation of the same geometry), the loop
// settles within 1e-4 m of its setpoint with both formulations, and the
// tangent with the signal ports (the spool reading the controller, the
// controller reading the sensor, the sensor reading the mechanics) equals
// central differences; and the loop's measured time constant is the one its
// linearisation's A matrix gives.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <string>

#include "monohydra/core/linearization.hpp"
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

// The stroke's approach to the 10 mm setpoint after t = 5 s decays as
// exp(-t / tau): tau measured by a least-squares fit of ln|e| over [8, 9.5]
// s, against -1 / Re(lambda) of A at t = 8 s, lambda the slowest mode the
// stroke sees (a mode of the chamber pressures' common level, slower still,
// moves no coordinate: its stroke share is 1e-4 of the loop's).
void expect_time_constant_of_linearisation(const std::string& formulation) {
  SCOPED_TRACE(formulation);
  const ModelFile file = position_control();
  Simulation sim(file, test::build_plugins(),
                 RunChoices{formulation, "", std::nullopt, std::nullopt});
  sim.start();
  const int stroke = sim.state_index("stroke");
  while (sim.time() < 8.0 - 1e-9) sim.step();
  const Linearization lin = linearize(sim, {"stroke"});
  double st = 0.0, se = 0.0, stt = 0.0, ste = 0.0;
  int count = 0;
  while (sim.time() < 9.5 - 1e-9) {
    sim.step();
    const double e = std::log(std::abs(sim.states()[stroke] - 0.01));
    st += sim.time();
    se += e;
    stt += sim.time() * sim.time();
    ste += sim.time() * e;
    ++count;
  }
  const double slope = (count * ste - st * se) / (count * stt - st * st);
  const double tau_measured = -1.0 / slope;
  // A in scaled states (Pa as MPa) for an accurate eigen-decomposition.
  const Eigen::Index n = lin.A.rows();
  Eigen::VectorXd scale(n);
  for (Eigen::Index i = 0; i < n; ++i) scale[i] = lin.states[i].unit == "Pa" ? 1e6 : 1.0;
  const Eigen::MatrixXd a = scale.cwiseInverse().asDiagonal() * lin.A * scale.asDiagonal();
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a);
  const Eigen::RowVectorXd c = lin.C.row(0) * scale.asDiagonal();
  std::vector<double> share(n);
  double most = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXcd v = eig.eigenvectors().col(i);
    share[i] = std::abs((c.cast<std::complex<double>>() * v)(0)) / v.norm();
    most = std::max(most, share[i]);
  }
  double slowest = -HUGE_VAL;
  for (Eigen::Index i = 0; i < n; ++i)
    if (share[i] > 1e-2 * most) slowest = std::max(slowest, eig.eigenvalues()[i].real());
  ASSERT_LT(slowest, 0.0);
  const double tau_linear = -1.0 / slowest;
  EXPECT_GT(tau_measured, 0.5);  // a slow tail indeed (the P part alone: 0.2 s)
  EXPECT_NEAR(tau_linear, tau_measured, 0.1 * tau_measured)
      << "measured " << tau_measured << " s, linearisation " << tau_linear << " s";
}

TEST(FourbarPositionControl, MeasuredTimeConstantIsTheLinearisationsWithin10PercentDoubleStep) {
  expect_time_constant_of_linearisation("double-step");
}

TEST(FourbarPositionControl, MeasuredTimeConstantIsTheLinearisationsWithin10PercentPenalty) {
  expect_time_constant_of_linearisation("penalty");
}

}  // namespace
}  // namespace mh
