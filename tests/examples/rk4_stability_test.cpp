// The explicit step's stability check (core/src/step/explicit_stability.cpp) with
// the example integrator examples/rk4: on a damped slider whose eigenvalues
// are known in closed form, the linearised rates give them, the plugin's own
// stages give RK4's amplification polynomial, and the largest stable step is
// the closed-form boundary 2.7853/|lambda|; on the double-step four-bar the
// paper's dt = 1 ms is flagged and 0.1 ms is not; with
// solver.explicit_stability: error the unstable run stops before its first
// step with the time, the step and the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>

#include "build_paths.hpp"
#include "hosts/cli_runner.hpp"
#include "monohydra/core/explicit_stability.hpp"
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

// RK4's amplification polynomial R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24.
std::complex<double> rk4_polynomial(std::complex<double> z) {
  return 1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)));
}

// The negative real boundary of RK4's stability region: the real root of
// |R(x)| = 1 below 0, R(x) = 1 + x + x^2/2 + x^3/6 + x^4/24 = 1 (bisected here).
double rk4_real_boundary() {
  double lo = -3.0;
  double hi = -2.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (std::abs(rk4_polynomial(mid)) > 1.0 ? lo : hi) = mid;
  }
  return lo;
}

constexpr double kMass = 2.0;        // kg
constexpr double kStiffness = 50.0;  // N/m

// A slider on a spring-damper (m x'' + c x' + k x = 0): eigenvalues
// (-c +- sqrt(c^2 - 4 m k)) / (2 m); `solver` more settings of its solver block.
std::string slider_text(double damping, double dt, const std::string& solver = "") {
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
    z0: 0.1
subsystems:
  - name: holder
    type: spring-damper
    points:
      a: {body: ground, at: [-1, 0, 0]}
      b: {body: slider, at: [0, 0, 0]}
    stiffness: )" + std::to_string(kStiffness) +
                           R"(
    damping: )" + std::to_string(damping) +
                           R"(
    free_length: 1.0
formulation: open-loop
integrator: rk4
solver: {dt: )" + std::to_string(dt) +
                           R"(, t_end: 1, tol_position: 1e-10)" + solver + R"(}
)";
  return text;
}

ModelFile slider(double damping, double dt) {
  return parse_model_text(slider_text(damping, dt), "slider.yaml");
}

TEST(ExplicitStability, TheStagesGiveRk4sPolynomialAtTheSlidersKnownEigenvalue) {
  const double c = 3.0;  // underdamped: lambda = -0.75 +- 4.943i 1/s
  const double dt = 0.05;
  const ModelFile file = slider(c, dt);
  Simulation sim(file, plugins(), RunChoices{"", "", std::nullopt, std::nullopt});
  sim.start();
  sim.step();
  const ExplicitStability& s = sim.explicit_stability();
  ASSERT_EQ(s.checks, 1);
  const std::complex<double> exact(-c / (2 * kMass),
                                   std::sqrt(4 * kMass * kStiffness - c * c) / (2 * kMass));
  // The linearisation by central differences of the rate solve.
  EXPECT_NEAR(s.eigenvalue.real(), exact.real(), 1e-6 * std::abs(exact)) << s.eigenvalue;
  EXPECT_NEAR(std::abs(s.eigenvalue.imag()), exact.imag(), 1e-6 * std::abs(exact));
  // The amplification from the plugin's own stages is RK4's polynomial at
  // the eigenvalue found, to round-off.
  EXPECT_NEAR(s.amplification, std::abs(rk4_polynomial(dt * s.eigenvalue)), 1e-12);
  EXPECT_LT(s.amplification, 1.0);
  EXPECT_FALSE(s.unstable);
  EXPECT_EQ(s.h, dt);
}

TEST(ExplicitStability, TheLargestStableStepIsTheClosedFormBoundaryOnTheRealAxis) {
  // Overdamped (c = 100 N s/m): real eigenvalues -0.505 and -49.49 1/s; the
  // stiff one bounds the step at 2.7853 / 49.49 = 56.3 ms.
  const double c = 100.0;
  const double stiff = (c + std::sqrt(c * c - 4 * kMass * kStiffness)) / (2 * kMass);
  const double bound = -rk4_real_boundary() / stiff;
  EXPECT_NEAR(-rk4_real_boundary(), 2.785293563405282, 1e-12);
  for (const double dt : {0.01, 0.08}) {
    const ModelFile file = slider(c, dt);
    Simulation sim(file, plugins(), RunChoices{"", "", std::nullopt, std::nullopt});
    sim.start();
    sim.step();
    const ExplicitStability& s = sim.explicit_stability();
    EXPECT_NEAR(s.stable_dt, bound, 0.01 * bound) << "dt = " << dt;
    EXPECT_EQ(s.unstable, dt > bound) << "dt = " << dt;
    // Beyond the bound the worst mode is the stiff one.
    if (s.unstable) {
      EXPECT_NEAR(s.eigenvalue.real(), -stiff, 1e-5 * stiff) << "dt = " << dt;
      EXPECT_GT(s.amplification, 1.0);
    }
    EXPECT_NEAR(s.amplification, std::abs(rk4_polynomial(dt * s.eigenvalue)), 1e-12);
  }
}

TEST(ExplicitStability, TheDoubleStepFourBarIsFlaggedAtOneMillisecondAndNotAtATenth) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  double bound = 0.0;
  for (const double dt : {1e-3, 1e-4}) {
    Simulation sim(file, plugins(), RunChoices{"double-step", "rk4", dt, 5 * dt});
    sim.start();
    for (int k = 0; k < 5; ++k) sim.step();
    const ExplicitStability& s = sim.explicit_stability();
    ASSERT_GE(s.checks, 1);
    EXPECT_EQ(s.unstable, dt == 1e-3) << "dt = " << dt << ": |R| = " << s.amplification;
    if (s.unstable) {
      EXPECT_GT(s.amplification, 1.01);
    }
    EXPECT_GT(s.stable_dt, 1e-4);
    EXPECT_LT(s.stable_dt, 1e-3);
    if (bound > 0.0) {
      EXPECT_NEAR(s.stable_dt, bound, 0.05 * bound);  // same state, same modes
    }
    bound = s.stable_dt;
  }
}

// An explicit integrator takes no Newton step and has no begin_step: asking
// for the step's tangent is refused with a reason (it once called through
// RK4's NULL begin_step and crashed `monohydra check`), and the run goes on.
TEST(ExplicitStability, TheTangentOfAnExplicitRunIsRefusedWithAReasonNotACrash) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, plugins(), RunChoices{"double-step", "rk4", 1e-4, 1e-3});
  sim.start();
  sim.step();
  EXPECT_TRUE(sim.explicit_integration());
  for (const auto& ask : {+[](Simulation& s) { (void)s.assembled_tangent(); },
                          +[](Simulation& s) { (void)s.finite_difference_tangent(); },
                          +[](Simulation& s) { (void)s.central_difference_tangent(); }}) {
    try {
      ask(sim);
      ADD_FAILURE() << "an explicit run gave a tangent";
    } catch (const SimulationError& err) {
      EXPECT_NE(std::string(err.what()).find("explicit"), std::string::npos) << err.what();
    }
  }
  const double t = sim.time();
  sim.step();
  EXPECT_GT(sim.time(), t);
}

TEST(ExplicitStability, WithTheErrorPolicyAnUnstableRunStopsBeforeItsFirstStep) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.explicit_stability = ExplicitStabilityPolicy::error;
  const RunChoices choices{"double-step", "rk4", 1e-3, 0.01};
  Simulation sim(file, plugins(), choices);
  sim.start();
  try {
    sim.step();
    FAIL() << "the unstable step was taken";
  } catch (const SimulationError& e) {
    EXPECT_EQ(e.step(), 1);
    EXPECT_NE(e.reason().find("unstable at h = 0.001 s"), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("stable below h ~"), std::string::npos) << e.what();
  }
  // off: no check at all.
  file.solver.explicit_stability = ExplicitStabilityPolicy::off;
  Simulation quiet(file, plugins(), choices);
  quiet.start();
  quiet.step();
  EXPECT_EQ(quiet.explicit_stability().checks, 0);
}

TEST(ExplicitStability, TheModelFileChoosesThePolicyAndABadOneIsNamed) {
  EXPECT_EQ(slider(3.0, 0.01).solver.explicit_stability, ExplicitStabilityPolicy::warn);
  EXPECT_EQ(parse_model_text(slider_text(3.0, 0.01, ", explicit_stability: error"), "e.yaml")
                .solver.explicit_stability,
            ExplicitStabilityPolicy::error);
  try {
    (void)parse_model_text(slider_text(3.0, 0.01, ", explicit_stability: loud"), "bad.yaml");
    FAIL() << "explicit_stability: loud was taken";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("solver.explicit_stability"), std::string::npos) << what;
    EXPECT_NE(what.find("expected error, warn or off"), std::string::npos) << what;
  }
}

// The check only looks: with it (at t = 0 and after the valve's event at
// 1 s) the run's states are bit for bit those without it.
TEST(ExplicitStability, TheCheckDoesNotChangeTheRun) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  const RunChoices choices{"double-step", "rk4", 1e-3, 1.1};
  Eigen::VectorXd z[2], y[2];
  int checks[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    file.solver.explicit_stability =
        k == 0 ? ExplicitStabilityPolicy::off : ExplicitStabilityPolicy::warn;
    Simulation sim(file, plugins(), choices);
    sim.start();
    for (int step = 0; step < 1100; ++step) sim.step();
    z[k] = sim.z();
    y[k] = sim.states();
    checks[k] = sim.explicit_stability().checks;
  }
  EXPECT_EQ(checks[0], 0);
  EXPECT_EQ(checks[1], 2);  // t = 0; the valve's event at 1 s (step 1000, the periodic one too)
  EXPECT_EQ(z[0], z[1]);
  EXPECT_EQ(y[0], y[1]);
}

// As a user sees it: compare's line under the table, and run stopped by
// --explicit-stability error.
TEST(ExplicitStability, CompareSaysItUnderTheTableAndRunStopsOnError) {
  const std::string env =
      "MONOHYDRA_PLUGIN_PATH=" + std::string(mh::test::paths::examples_dir) + "/rk4 ";
  const std::string model = test::source_path("models/fourbar.yaml");
  const auto at_1ms = mh::test::run_cli(
      "compare " + model + " --formulations double-step --integrators trapezoidal,rk4 --t-end 0.01",
      env);
  EXPECT_EQ(at_1ms.code, 0) << at_1ms.output;
  EXPECT_NE(at_1ms.output.find("explicit step: rk4 unstable: dt = 1 ms, |R| = "), std::string::npos)
      << at_1ms.output;
  EXPECT_NE(at_1ms.output.find("stable below ~ 0.1"), std::string::npos) << at_1ms.output;
  EXPECT_EQ(at_1ms.output.find("explicit step: trapezoidal"), std::string::npos);  // implicit
  const auto at_01ms = mh::test::run_cli("compare " + model +
                                             " --formulations double-step --integrators "
                                             "trapezoidal,rk4 --dt 1e-4 --t-end 0.002",
                                         env);
  EXPECT_EQ(at_01ms.code, 0) << at_01ms.output;
  EXPECT_NE(at_01ms.output.find("explicit step: rk4 stable: dt = 0.1 ms"), std::string::npos)
      << at_01ms.output;
  const auto strict = mh::test::run_cli(
      "run " + model + " --integrator rk4 --t-end 0.01 --explicit-stability error", env);
  EXPECT_EQ(strict.code, 1) << strict.output;
  EXPECT_NE(strict.output.find("t = 0.001 s, step 1: the explicit integrator 'rk4' is unstable"),
            std::string::npos)
      << strict.output;
}

}  // namespace
}  // namespace mh
