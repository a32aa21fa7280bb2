// Signal ports into the hydraulics: a flow source (a pump's delivery) driven
// by a PI on a pressure sensor holds a hose's pressure at its setpoint
// against a throttle to the tank, and a pressure source follows its table.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

std::string circuit(const std::string& supply) {
  return R"(units: {length: m, mass: kg, time: s, angle: rad}
name: pressure-loop
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
inputs:
  - {name: p_set, unit: Pa, table: [[0, 3e6], [0.2, 3e6], [0.2, 5e6]]}
subsystems:
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 3e6}
  - {name: gauge, type: pressure-sensor, ports: {a: n}}
)" + supply +
         R"(
  - {name: tank, type: pressure-source, ports: {p: drain}, pressure: 1e5}
  - {name: line, type: throttle, ports: {a: n, b: drain}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";
}

const char* kPumpUnderPi =
    "  - {name: loop, type: pi-controller, setpoint: p_set, measurement: gauge.p, kp: 2e-11, "
    "ki: 2e-9, output_min: 0, output_max: 2e-4}\n"
    "  - {name: pump, type: flow-source, ports: {p: n}, flow: loop.u}";

TEST(SignalPortIntoHydraulics, APumpUnderPiHoldsTheSetpointAndDeliversTheThrottlesFlow) {
  const ModelFile file = parse_model_text(circuit(kPumpUnderPi), "loop.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  while (sim.time() < 1.0 - 1e-9) sim.step();
  const int p = sim.state_index("gauge.p"), q = sim.output_index("line.q");
  const int delivered = sim.output_index("pump.q");
  ASSERT_GE(p, 0);
  ASSERT_GE(q, 0);
  ASSERT_GE(delivered, 0);
  EXPECT_NEAR(sim.states()[p], 5e6, 1.0);  // Pa: the new setpoint, held
  EXPECT_NEAR(sim.outputs()[delivered], sim.outputs()[q], 1e-6 * sim.outputs()[q]);  // balance
  // The throttle's turbulent flow at 5 MPa - 0.1 MPa (Eq. 24).
  const double c_vt = 0.7 * 1e-6 * std::sqrt(2.0 / 850.0);
  EXPECT_NEAR(sim.outputs()[q], c_vt * std::sqrt(5e6 - 1e5), 1e-9);
}

TEST(SignalPortIntoHydraulics, TangentOfThePressureLoopEqualsCentralDifferences) {
  const ModelFile file = parse_model_text(circuit(kPumpUnderPi), "loop.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  while (sim.time() < 0.21 - 1e-9) sim.step();  // just after the step: the loop is acting
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  for (Eigen::Index r = 0; r < J.rows(); ++r) {
    const double scale = std::max(J_cd.row(r).cwiseAbs().maxCoeff(), 1e-300);
    for (Eigen::Index c = 0; c < J.cols(); ++c)
      EXPECT_NEAR(J(r, c), J_cd(r, c), 1e-5 * scale) << "row " << r << ", column " << c;
  }
}

TEST(SignalPortIntoHydraulics, APressureSourceFollowsItsTable) {
  const ModelFile file = parse_model_text(
      circuit("  - {name: pump, type: pressure-source, ports: {p: n}, pressure: [[0, 3e6], [0.5, "
              "4e6], [1, 4e6]]}"),
      "table.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  const int p = sim.state_index("gauge.p");
  double worst = 0.0;
  while (sim.time() < 1.0 - 1e-9) {
    sim.step();
    const double t = sim.time(), expected = t < 0.5 ? 3e6 + 2e6 * t : 4e6;
    worst = std::max(worst, std::abs(sim.states()[p] - expected));
  }
  EXPECT_LT(worst, 1e-3);
}

}  // namespace
}  // namespace mh
