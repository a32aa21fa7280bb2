// The mechanics subsystem plugin: a spring-damper against the closed-form
// damped oscillator, the Maxwell element's energy balance and analytic
// tangent block, and option errors that name the file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A 2 kg slider on a prismatic joint along X, tied to the ground by a
// spring-damper along the same line: m x'' + c x' + k x = 0.
std::string oscillator(const std::string& options) {
  return R"(
units: {length: m, mass: kg, time: s, angle: rad}
name: oscillator
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: 2.0
    com: [0, 0, 0]
    inertia: [1, 1, 1]
    z0: 0.1
subsystems:
  - name: spring
    type: spring-damper
    points:
      a: {body: ground, at: [-1, 0, 0]}
      b: {body: slider, at: [0, 0, 0]}
)" + options +
         R"(
formulation: open-loop
solver: {dt: 0.001, t_end: 2}
)";
}

const std::string kOscillatorOptions = "    stiffness: 200\n    damping: 4\n    free_length: 1.0\n";

// What a host that draws the run sees (visual.h): a link between the
// spring's two points, named after the instance, coloured by nothing.
TEST(SpringDamper, DeclaresItsLookAsALinkBetweenItsPoints) {
  const ModelFile file = parse_model_text(oscillator(kOscillatorOptions), "oscillator.yaml");
  const Simulation sim(file, test::build_plugins());
  ASSERT_EQ(sim.visuals().size(), 1u);
  const Visual& v = sim.visuals().front();
  EXPECT_EQ(v.instance, "spring");
  EXPECT_EQ(v.kind, Visual::Kind::link);
  EXPECT_EQ(v.a.body, kGround);
  EXPECT_TRUE(v.a.p_B.isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_EQ(v.b.body, 0);
  EXPECT_GT(v.rod_diameter, 0.0);
  EXPECT_EQ(v.state_a, -1);
  EXPECT_EQ(v.state_b, -1);
}

TEST(SpringDamper, MatchesTheClosedFormDampedOscillator) {
  const ModelFile file = parse_model_text(oscillator(kOscillatorOptions), "oscillator.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  const double m = 2.0, k = 200.0, c = 4.0, x0 = 0.1;
  const double w0 = std::sqrt(k / m), zeta = c / (2.0 * m * w0);
  const double wd = w0 * std::sqrt(1.0 - zeta * zeta);
  double max_err = 0.0, max_energy_gap = 0.0;
  while (sim.time() < 2.0 - 1e-12) {
    sim.step();
    const double t = sim.time();
    const double exact =
        std::exp(-zeta * w0 * t) * (x0 * std::cos(wd * t) + zeta * w0 * x0 / wd * std::sin(wd * t));
    max_err = std::max(max_err, std::abs(sim.z()[0] - exact));
    // Work done by the element = -(spring energy change + damper dissipation).
    max_energy_gap = std::max(max_energy_gap,
                              std::abs(sim.work() + sim.stored_energy() + sim.dissipated_energy()));
  }
  EXPECT_LT(max_err, 5e-5);                 // 0.05 % of the 0.1 m amplitude
  EXPECT_GT(sim.dissipated_energy(), 0.5);  // most of the initial 1 J is gone
  EXPECT_LT(max_energy_gap, 1e-4);
  EXPECT_LT(std::abs(sim.drift()), 1e-4);
}

TEST(MaxwellElement, PendulumBalancesEnergyWithTheDampersDissipatedWork) {
  const ModelFile file = load_model_file(test::source_path("models/maxwell-pendulum.yaml"));
  Simulation sim(file, test::build_plugins());
  ASSERT_EQ(sim.state_names().size(), 1u);
  EXPECT_EQ(sim.state_names()[0], "delta");
  sim.start();
  double max_drift = 0.0, max_balance = 0.0;
  while (sim.time() < 10.0 - 1e-9) {
    sim.step();
    max_drift = std::max(max_drift, std::abs(sim.drift()));
    // KE + PE + spring energy + dissipated = 0 (all relative to t = 0).
    max_balance = std::max(max_balance, std::abs(sim.kinetic_energy() + sim.potential_energy() +
                                                 sim.stored_energy() + sim.dissipated_energy()));
  }
  EXPECT_GT(sim.dissipated_energy(), 1.0);  // the damper does real work
  EXPECT_LT(max_drift, 1e-3);
  EXPECT_LT(max_balance, 1e-3);
}

// A spring-damper between two moving bodies of a spatial double pendulum (off
// any symmetry line): its analytic point-force derivatives make the
// whole open-loop tangent, which equals central differences of the residual.
TEST(SpringDamper, AnalyticTangentBetweenTwoMovingBodiesEqualsCentralDifferences) {
  const ModelFile file = parse_model_text(R"(
units: {length: m, mass: kg, time: s, angle: deg}
name: sprung-pendulum
gravity: [0, -9.81, 0]
bodies:
  - name: upper
    parent: ground
    joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]}
    mass: 1.5
    shape: {type: beam, length: 1.0}
    z0: -60
  - name: lower
    parent: upper
    joint: {type: revolute, at: [1, 0, 0], axis: [0, 1, 0]}
    mass: 1.0
    shape: {type: beam, length: 0.8}
    z0: 30
subsystems:
  - name: spring
    type: spring-damper
    points:
      a: {body: upper, at: [0.3, 0.1, 0]}
      b: {body: lower, at: [0.7, 0, 0.05]}
    stiffness: 300
    damping: 5
    free_length: 0.5
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)",
                                          "sprung-pendulum.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  for (int i = 0; i < 150; ++i) sim.step();
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  ASSERT_EQ(J.rows(), 2);
  EXPECT_LT((J - J_cd).cwiseAbs().maxCoeff(), 1e-6 * J_cd.cwiseAbs().maxCoeff()) << J << "\n\n"
                                                                                 << J_cd;
}

TEST(MaxwellElement, AnalyticStateBlockEqualsForwardDifferences) {
  const ModelFile file = load_model_file(test::source_path("models/maxwell-pendulum.yaml"));
  Simulation sim(file, test::build_plugins());
  sim.start();
  for (int i = 0; i < 200; ++i) sim.step();
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_fd = sim.finite_difference_tangent();
  ASSERT_EQ(J.rows(), 2);
  // (delta, delta): k + (2 / dt) c, analytic in J.
  EXPECT_NEAR(J(1, 1), 400.0 + 2.0 / 1e-3 * 20.0, 1e-9);
  EXPECT_NEAR(J(1, 1), J_fd(1, 1), 1e-6 * std::abs(J(1, 1)));
  EXPECT_LT((J - J_fd).norm(), 1e-5 * J_fd.norm());
}

std::string setup_error(const std::string& options) {
  try {
    const ModelFile file = parse_model_text(oscillator(options), "oscillator.yaml");
    Simulation sim(file, test::build_plugins());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SpringDamper, MisspelledOptionIsRejectedWithFileLineAndTheKnownKeys) {
  const std::string err =
      setup_error("    stiffnes: 200\n    stiffness: 1\n    free_length: 1.0\n");
  EXPECT_EQ(err,
            "oscillator.yaml:19:15: subsystem 'spring' (spring-damper) option 'stiffnes': "
            "unknown option (expected one of: damping, free_length, stiffness)");
}

TEST(SpringDamper, MissingRequiredOptionNamesIt) {
  const std::string err = setup_error("    stiffness: 200\n");
  EXPECT_NE(err.find("oscillator.yaml:"), std::string::npos) << err;
  EXPECT_NE(err.find("option 'free_length': required option is missing (expected a number)"),
            std::string::npos)
      << err;
}

TEST(SpringDamper, NegativeStiffnessIsRejectedAtItsLine) {
  const std::string err = setup_error("    stiffness: -5\n    free_length: 1.0\n");
  EXPECT_EQ(err,
            "oscillator.yaml:19:16: subsystem 'spring' (spring-damper) option 'stiffness': "
            "expected a non-negative stiffness (N/m), got '-5'");
}

TEST(SpringDamper, NonNumericOptionIsRejected) {
  const std::string err = setup_error("    stiffness: stiff\n    free_length: 1.0\n");
  EXPECT_NE(err.find("option 'stiffness': expected a finite number, got 'stiff'"),
            std::string::npos)
      << err;
}

}  // namespace
}  // namespace mh
