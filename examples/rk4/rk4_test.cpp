// The example integrator's unit test, against the installed test host alone
// (monohydra::testhost, docs/plugin-guide.md): on a damped slider, m x'' =
// -k x - c x', its error against the closed form falls by 2^4 = 16 when the
// step halves (fourth order), and on a stiff spring beyond its stability
// bound (h sqrt(k/m) > 2.78) the run stops with a clear status, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <monohydra/testhost.hpp>
#include <string>

namespace {

namespace th = monohydra::testhost;

constexpr double kMass = 2.0;   // kg
constexpr double kDamping = 3;  // N s/m
constexpr double kX0 = 0.1;     // m

// A slider on the x axis held between the ground at x = -1 and its origin by
// a spring-damper of free length 1 (its force linear in x), from x0 at rest.
th::Model slider(double stiffness) {
  return th::Model::text(R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: )" + std::to_string(kMass) +
                             R"(, com: [0, 0, 0], inertia: [1, 1, 1], z0: )" + std::to_string(kX0) +
                             R"(}
subsystems:
  - {name: holder, type: spring-damper, stiffness: )" +
                             std::to_string(stiffness) + R"(, damping: )" +
                             std::to_string(kDamping) + R"(, free_length: 1.0,
     points: {a: {body: ground, at: [-1, 0, 0]}, b: {body: slider, at: [0, 0, 0]}}}
formulation: open-loop
integrator: rk4
solver: {dt: 0.01, t_end: 1, tol_position: 1e-10}
)",
                         "slider.yaml");
}

// The underdamped closed form from x0 at rest.
double exact(double k, double t) {
  const double w = std::sqrt(k / kMass), zeta = kDamping / (2.0 * std::sqrt(k * kMass));
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  return kX0 * std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
}

const th::Host& host() {
  static const th::Host h(RK4_LIBRARY, "rk4");
  return h;
}

// The largest |x - exact| over 1 s at step h.
double worst_error(double h) {
  constexpr double k = 50.0;  // N/m: h sqrt(k/m) = 0.05, well inside the bound
  const th::Series s = host().run(slider(k), static_cast<int>(std::lround(1.0 / h)), h);
  EXPECT_TRUE(s.ok) << s.status;
  const std::vector<double> x = s.column("z1");
  double worst = 0.0;
  for (size_t i = 0; i < x.size(); ++i)
    worst = std::max(worst, std::abs(x[i] - exact(k, s.time[i])));
  return worst;
}

TEST(Rk4, ErrorFallsBySixteenWhenTheStepHalvesOnADampedOscillator) {
  const double e1 = worst_error(0.01), e2 = worst_error(0.005);
  std::printf("  damped slider: h = 0.01 %.3e, h = 0.005 %.3e, ratio %.2f\n", e1, e2, e1 / e2);
  EXPECT_GT(e1 / e2, 14.0);
  EXPECT_LT(e1 / e2, 18.0);
  EXPECT_LT(e2, 1e-7);  // m
}

TEST(Rk4, StopsWithAClearStatusBeyondItsStabilityBound) {
  // k = 2e6 N/m: h sqrt(k/m) = 10 at h = 0.01, far beyond RK4's 2.78.
  const th::Series s = host().run(slider(2e6), 100);
  std::printf("  k = 2e6 N/m at h = 0.01 s: %s\n", s.status.c_str());
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.status.rfind("FAILED at t = ", 0), 0u) << s.status;
  EXPECT_NE(s.status.find(", step "), std::string::npos) << s.status;
}

TEST(Rk4, SurvivesCreateAndDestroyCycles) {
  EXPECT_EQ(host().create_destroy(slider(50.0), 5), "");
}

}  // namespace
