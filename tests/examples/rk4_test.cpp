// The example integrator examples/rk4, built against the installed SDK alone
// (build_examples.cmake), driven by the host's explicit stages
// (core/src/step/explicit_step.cpp): fourth order against closed forms (a damped
// slider and a slider on a Maxwell element, whose damper elongation is a
// first-order state), the same motion as the trapezoidal rule on the
// four-bar's mechanics, and a clear failure, never a crash, where the stiff
// hydraulics put it outside its stability bound.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <string>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// The build's plugins and the example rk4.
const PluginRegistry& plugins() {
  return test::build_plugins_with(std::string(mh::test::paths::examples_dir) + "/rk4/rk4.so");
}

constexpr double kMass = 2.0;        // kg
constexpr double kStiffness = 50.0;  // N/m
constexpr double kDamping = 3.0;     // N s/m
constexpr double kX0 = 0.1;          // m

// A slider on the x axis held by `element` between the ground at x = -1 and
// its origin (free length 1, so the element's force is linear in x), started
// at x0 at rest.
ModelFile slider(const std::string& element, const std::string& states) {
  const std::string text = R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: )" + std::to_string(kMass) +
                           R"(
    com: [0, 0, 0]
    inertia: [1, 1, 1]
    z0: )" + std::to_string(kX0) +
                           R"(
subsystems:
  - name: holder
    type: )" + element + R"(
    points:
      a: {body: ground, at: [-1, 0, 0]}
      b: {body: slider, at: [0, 0, 0]}
)" + states + R"(
    stiffness: )" + std::to_string(kStiffness) +
                           R"(
    damping: )" + std::to_string(kDamping) +
                           R"(
    free_length: 1.0
formulation: open-loop
integrator: rk4
solver: {dt: 0.01, t_end: 1, tol_position: 1e-10}
)";
  return parse_model_text(text, element + "-slider.yaml");
}

// The closed form of the linear system s' = A s from s0 at t.
Eigen::VectorXd exact(const Eigen::MatrixXd& a, const Eigen::VectorXd& s0, double t) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(a);
  const Eigen::MatrixXcd v = es.eigenvectors();
  const Eigen::VectorXcd c = v.partialPivLu().solve(s0.cast<std::complex<double>>());
  Eigen::VectorXcd e(c.size());
  for (Eigen::Index i = 0; i < c.size(); ++i) e[i] = std::exp(es.eigenvalues()[i] * t) * c[i];
  return (v * e).real();
}

// The largest error of x (and of the state delta, when there is one) over
// 1 s at step h against the closed form of A.
double worst_error(const ModelFile& file, const Eigen::MatrixXd& a, const Eigen::VectorXd& s0,
                   double h) {
  Simulation sim(file, plugins(), RunChoices{"", "rk4", h, 1.0});
  sim.start();
  double worst = 0.0;
  while (sim.time() < 1.0 - 1e-9) {
    sim.step();
    const Eigen::VectorXd s = exact(a, s0, sim.time());
    worst = std::max(worst, std::abs(sim.z()[0] - s[0]));
    worst = std::max(worst, std::abs(sim.zd()[0] - s[1]));
    if (s.size() > 2) worst = std::max(worst, std::abs(sim.states()[0] - s[2]));
  }
  return worst;
}

TEST(Rk4ThroughTheHost, IsFourthOrderOnADampedSlider) {
  // m x'' = -k x - c x'
  Eigen::MatrixXd a(2, 2);
  a << 0.0, 1.0, -kStiffness / kMass, -kDamping / kMass;
  const Eigen::Vector2d s0(kX0, 0.0);
  const ModelFile file = slider("spring-damper", "");
  const double e1 = worst_error(file, a, s0, 0.01), e2 = worst_error(file, a, s0, 0.005);
  std::printf("  damped slider: h = 0.01 %.3e, h = 0.005 %.3e, ratio %.2f\n", e1, e2, e1 / e2);
  EXPECT_GT(e1 / e2, 14.0);
  EXPECT_LT(e1 / e2, 18.0);
  EXPECT_LT(e2, 1e-6);
}

TEST(Rk4ThroughTheHost, IsFourthOrderWithAFirstOrderSubsystemState) {
  // m x'' = -k (x - delta), c delta' = k (x - delta): the host solves the
  // element's row for delta' at every stage.
  Eigen::MatrixXd a(3, 3);
  a << 0.0, 1.0, 0.0, -kStiffness / kMass, 0.0, kStiffness / kMass, kStiffness / kDamping, 0.0,
      -kStiffness / kDamping;
  const Eigen::Vector3d s0(kX0, 0.0, 0.0);
  const ModelFile file = slider("maxwell", "    states: {delta: delta}");
  const double e1 = worst_error(file, a, s0, 0.01), e2 = worst_error(file, a, s0, 0.005);
  std::printf("  Maxwell slider: h = 0.01 %.3e, h = 0.005 %.3e, ratio %.2f\n", e1, e2, e1 / e2);
  EXPECT_GT(e1 / e2, 14.0);
  EXPECT_LT(e1 / e2, 18.0);
}

// The four-bar at the paper's step with the penalty formulation: its stiff
// penalty and hydraulics put RK4 outside its stability bound within a few
// steps; the run stops with the time, the step and the reason, never a crash.
TEST(Rk4ThroughTheHost, FailsClearlyOnThePenaltyFourBarAtTheImplicitStep) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, plugins(), RunChoices{"penalty", "rk4", 1e-3, 0.5});
  sim.start();
  try {
    while (sim.time() < 0.5 - 1e-9) sim.step();
    FAIL() << "RK4 at 1 ms ran the penalty four-bar to the end";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("t = ", 0), 0u) << what;
    EXPECT_NE(what.find(", step "), std::string::npos) << what;
    EXPECT_LT(e.time(), 0.5);
    EXPECT_FALSE(e.reason().empty());
  }
}

}  // namespace
}  // namespace mh
