// The control plugin library's signal blocks against closed forms: each block
// driven by time tables, its output state compared with the solution of its
// equation; the PI's anti-windup against its bounded steady state; and the
// signal graph's tangent against central differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A model with one idle slider and the given subsystems (YAML list items).
std::string blocks_model(const std::string& subsystems, double t_end) {
  return R"(units: {length: m, mass: kg, time: s, angle: rad}
name: blocks
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
)" + subsystems +
         "formulation: open-loop\nsolver: {dt: 0.001, t_end: " + std::to_string(t_end) + "}\n";
}

struct BlockRun {
  explicit BlockRun(const std::string& subsystems, double t_end = 1.0)
      : file(parse_model_text(blocks_model(subsystems, t_end), "blocks.yaml")),
        sim(file, test::build_plugins()) {
    sim.start();
  }
  double state(const std::string& name) const {
    const int i = sim.state_index(name);
    EXPECT_GE(i, 0) << name;
    return i < 0 ? NAN : sim.states()[i];
  }
  ModelFile file;
  Simulation sim;
};

TEST(FirstOrderLag, FollowsAStepAsKTimesOneMinusExpOfMinusTOverT) {
  BlockRun run(
      "  - {name: lag, type: first-order-lag, input: [[0, 1], [1, 1]], time_constant: 0.05, "
      "gain: 2}\n");
  double worst = 0.0;
  while (run.sim.time() < 0.5 - 1e-12) {
    run.sim.step();
    const double exact = 2.0 * (1.0 - std::exp(-run.sim.time() / 0.05));
    worst = std::max(worst, std::abs(run.state("lag.y") - exact));
  }
  // The trapezoidal rule's error, (h/T)^2 / 12 of the response at most.
  EXPECT_LT(worst, 2.0 * (0.001 / 0.05) * (0.001 / 0.05) / 12.0);
  EXPECT_GT(run.state("lag.y"), 1.99);
}

TEST(GainSumSaturation, GiveTheirAlgebraicValuesAtEveryStep) {
  BlockRun run(
      "  - {name: k, type: gain, input: [[0, -1], [1, 3]], gain: 2.5}\n"
      "  - {name: d, type: sum, a: k.y, b: [[0, 0.5], [1, 0.5]], k_b: -1, c: [[0, 0], [1, 1]], "
      "k_c: 0.25}\n"
      "  - {name: sat, type: saturation, input: d.y, lower: -2, upper: 4}\n");
  double worst = 0.0;
  bool hit_lower = false, hit_upper = false;
  while (run.sim.time() < 1.0 - 1e-12) {
    run.sim.step();
    const double t = run.sim.time(), u = -1.0 + 4.0 * t;
    const double k = 2.5 * u, d = k - 0.5 + 0.25 * t;
    const double sat = std::clamp(d, -2.0, 4.0);
    hit_lower = hit_lower || d < -2.0;
    hit_upper = hit_upper || d > 4.0;
    worst = std::max({worst, std::abs(run.state("k.y") - k), std::abs(run.state("d.y") - d),
                      std::abs(run.state("sat.y") - sat)});
  }
  EXPECT_TRUE(hit_lower && hit_upper);  // both limits were crossed
  EXPECT_LT(worst, 1e-9);
}

TEST(RateLimiter, RisesAndFallsAtItsLimitsAndThenHoldsTheInput) {
  BlockRun run(
      "  - {name: r, type: rate-limiter, input: [[0, 0], [0.1, 0], [0.1, 1], [0.6, 1], "
      "[0.6, 0], [2, 0]], rising: 4, falling: 2, time_constant: 0.005}\n",
      2.0);
  double rising = 0.0, tracking = 0.0, held = 0.0, falling_a = 0.0, falling_b = 0.0;
  while (run.sim.time() < 1.2 - 1e-12) {
    run.sim.step();
    const double t = run.sim.time(), y = run.state("r.y");
    if (std::abs(t - 0.15) < 1e-9) rising = y;
    if (std::abs(t - 0.45) < 1e-9) tracking = y;
    if (std::abs(t - 0.60) < 1e-9) held = y;
    if (std::abs(t - 0.75) < 1e-9) falling_a = y;
    if (std::abs(t - 0.85) < 1e-9) falling_b = y;
  }
  EXPECT_NEAR(rising, 4.0 * 0.05, 1e-9);  // 4 /s from the step at t = 0.1
  // The limit ends where (1 - y) / T = 4 (y = 0.98 at t = 0.345), then y
  // tracks the input with T = 5 ms.
  EXPECT_NEAR(tracking, 1.0, 1e-6);
  EXPECT_NEAR(held, 1.0, 1e-6);
  EXPECT_NEAR(falling_a - falling_b, 2.0 * 0.1, 1e-9);  // 2 /s down from t = 0.6
  EXPECT_NEAR(run.state("r.y"), 0.0, 1e-6);
}

// A constant error e drives v = kp e + i up until u saturates at output_max;
// back-calculation then holds i where di/dt = ki e + (u - v)/Tt = 0:
// v = u_max + ki e Tt, so i = u_max + ki e Tt - kp e (no windup beyond it).
TEST(PiController, AntiWindupHoldsTheIntegralAtItsBackCalculatedBound) {
  BlockRun run(
      "  - {name: pi, type: pi-controller, setpoint: [[0, 1], [1, 1]], measurement: [[0, 0.5], "
      "[1, 0.5]], kp: 2, ki: 8, output_min: -1.5, output_max: 1.5, tracking_time: 0.05}\n",
      3.0);
  const double e = 0.5, kp = 2.0, ki = 8.0, tt = 0.05, u_max = 1.5;
  // Before the limit: u = kp e + ki e t (t_sat = (u_max - kp e) / (ki e) = 0.125 s).
  while (run.sim.time() < 0.1 - 1e-12) run.sim.step();
  EXPECT_NEAR(run.state("pi.u"), kp * e + ki * e * 0.1, 1e-9);
  while (run.sim.time() < 3.0 - 1e-12) run.sim.step();
  EXPECT_NEAR(run.state("pi.u"), u_max, 1e-12);
  EXPECT_NEAR(run.state("pi.i"), u_max + ki * e * tt - kp * e, 1e-6);
}

// A ramp error e = a t: w lags it by a Tf, so with no limit
// u = kp a t + ki a t^2 / 2 + kd a (1 - exp(-t / Tf)).
TEST(PidController, MatchesTheClosedFormResponseToARampError) {
  BlockRun run(
      "  - {name: pid, type: pid-controller, setpoint: [[0, 0], [2, 4]], measurement: [[0, 0], "
      "[2, 0]], kp: 1.5, ki: 3, kd: 0.2, filter_time_constant: 0.02}\n");
  const double a = 2.0, kp = 1.5, ki = 3.0, kd = 0.2, tf = 0.02;
  double worst = 0.0;
  while (run.sim.time() < 1.0 - 1e-12) {
    run.sim.step();
    const double t = run.sim.time();
    const double exact = kp * a * t + ki * a * t * t / 2.0 + kd * a * (1.0 - std::exp(-t / tf));
    worst = std::max(worst, std::abs(run.state("pid.u") - exact));
  }
  EXPECT_LT(worst, 1e-3 * kd * a);  // the filter's trapezoidal error, (h/Tf)^2/12 of kd a
}

// A state signal read by a block above its writer is refused with the order.
TEST(SignalPort, RefusesAStateOfAnInstanceListedBelowAndNamesTheChoices) {
  try {
    BlockRun run(
        "  - {name: k, type: gain, input: later.y, gain: 1}\n"
        "  - {name: later, type: gain, input: [[0, 1], [1, 1]], gain: 1}\n");
    FAIL() << "a state of an instance below was accepted";
  } catch (const std::exception& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("blocks.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("input"), std::string::npos) << what;
    EXPECT_NE(what.find("'later.y'"), std::string::npos) << what;
    EXPECT_NE(what.find("listed above"), std::string::npos) << what;
  }
}

// The blocks' analytic rows (a chain through every kink) give the tangent
// that central differences of the residual give.
TEST(SignalPort, TangentOfAChainOfBlocksEqualsCentralDifferences) {
  BlockRun run(
      "  - {name: lag, type: first-order-lag, input: [[0, 0], [1, 3]], time_constant: 0.05}\n"
      "  - {name: k, type: gain, input: lag.y, gain: 2}\n"
      "  - {name: sat, type: saturation, input: k.y, lower: -1, upper: 4}\n"
      "  - {name: r, type: rate-limiter, input: sat.y, rising: 50, time_constant: 0.02}\n"
      "  - {name: pid, type: pid-controller, setpoint: r.y, measurement: lag.y, kp: 1, ki: 2, "
      "kd: 0.05, output_min: -3, output_max: 3}\n");
  for (int i = 0; i < 300; ++i) run.sim.step();
  const Eigen::MatrixXd J = run.sim.assembled_tangent();
  const Eigen::MatrixXd J_cd = run.sim.central_difference_tangent();
  ASSERT_EQ(J.rows(), J_cd.rows());
  EXPECT_GT(J_cd.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((J - J_cd).cwiseAbs().maxCoeff(), 1e-6 * J_cd.cwiseAbs().maxCoeff())
      << "analytic\n"
      << J << "\ndifferences\n"
      << J_cd;
}

}  // namespace
}  // namespace mh
