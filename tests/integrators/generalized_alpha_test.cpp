// The generalized-alpha method: its dissipation is what rho_inf asks for.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <complex>
#include <cstdio>

#include "problems.hpp"

namespace mh_test {
namespace {

// The roots of l^3 - p2 l^2 - p1 l - p0 (Durand-Kerner).
std::array<std::complex<double>, 3> cubic_roots(double p2, double p1, double p0) {
  using C = std::complex<double>;
  std::array<C, 3> r{C(0.4, 0.9), C(0.4, 0.9) * C(0.4, 0.9),
                     C(0.4, 0.9) * C(0.4, 0.9) * C(0.4, 0.9)};
  const auto poly = [&](C l) { return ((l - p2) * l - p1) * l - p0; };
  for (int it = 0; it < 500; ++it)
    for (size_t i = 0; i < 3; ++i) {
      C d = 1.0;
      for (size_t j = 0; j < 3; ++j)
        if (j != i) d *= r[i] - r[j];
      r[i] -= poly(r[i]) / d;
    }
  return r;
}

// The spectral radius of the step's amplification matrix on x'' + w^2 x = 0
// at h w = hw, measured from the free response: its state (x, xd, a) is 3
// numbers, so by Cayley-Hamilton x_n and xd_n obey s_{n+3} = p2 s_{n+2} +
// p1 s_{n+1} + p0 s_n with the characteristic polynomial's coefficients,
// fitted by least squares over the first steps; the radius is its largest root.
double spectral_radius(const std::map<std::string, double>& options, double hw, int steps) {
  const double w = hw;  // h = 1
  const LinearProblem p{
      {MH_UNKNOWN_SECOND_ORDER}, {1.0}, {0.0}, {w * w}, [](double, double* f) { f[0] = 0.0; }};
  std::vector<std::array<double, 2>> seq;
  const State s0{0.0, {1.0}, {0.3 * w}, {-w * w}};
  seq.push_back({s0.x[0], s0.xd[0] / w});
  Integrator integ("generalized-alpha", options);
  run(integ, p, s0, std::vector<double>(static_cast<size_t>(steps), 1.0), [&](const State& s) {
    seq.push_back({s.x[0], s.xd[0] / w});
  });
  // Normal equations of the fit, normalised per equation.
  double N[3][3] = {}, b[3] = {};
  for (size_t n = 0; n + 3 < seq.size(); ++n)
    for (size_t k = 0; k < 2; ++k) {
      const double row[3] = {seq[n + 2][k], seq[n + 1][k], seq[n][k]};
      const double scale =
          1.0 / std::max({std::abs(row[0]), std::abs(row[1]), std::abs(row[2]), 1e-300});
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) N[i][j] += row[i] * row[j] * scale * scale;
        b[i] += row[i] * seq[n + 3][k] * scale * scale;
      }
    }
  std::vector<double> A(9), rhs(b, b + 3);
  for (size_t i = 0; i < 3; ++i)
    for (size_t j = 0; j < 3; ++j) A[3 * i + j] = N[i][j];
  solve_dense(A, rhs);
  double radius = 0.0;
  for (const auto& r : cubic_roots(rhs[0], rhs[1], rhs[2])) radius = std::max(radius, std::abs(r));
  return radius;
}

TEST(GeneralizedAlpha, SpectralRadiusAtInfinityIsRhoInf) {
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    const double measured = spectral_radius({{"rho_inf", rho}}, 1e6, 6);
    std::printf("  generalized-alpha rho_inf=%.1f: spectral radius at h w = 1e6: %.6f\n", rho,
                measured);
    EXPECT_NEAR(measured, rho, 1e-3) << "rho_inf = " << rho;
  }
}

}  // namespace
}  // namespace mh_test

namespace mh_test {
namespace {

// x'' + x = 0 over 1e4 steps of h = 0.1: max |E - E0| / E0, and the run's x.
double energy_drift(const Case& c, std::vector<double>* xs = nullptr) {
  const LinearProblem p{
      {MH_UNKNOWN_SECOND_ORDER}, {1.0}, {0.0}, {1.0}, [](double, double* f) { f[0] = 0.0; }};
  double worst = 0.0;
  Integrator integ(c.id, c.options);
  run(integ, p, State{0.0, {1.0}, {0.0}, {-1.0}}, uniform_steps(1000.0, 0.1), [&](const State& s) {
    worst = std::max(worst, std::abs(0.5 * (s.xd[0] * s.xd[0] + s.x[0] * s.x[0]) - 0.5) / 0.5);
    if (xs != nullptr) xs->push_back(s.x[0]);
  });
  return worst;
}

// rho_inf = 1: alpha_m = alpha_f = 1/2, gamma = 1/2, beta = 1/4, a = xdd: the
// trapezoidal rule, with no numerical dissipation.
TEST(GeneralizedAlpha, RhoInfOneIsTheTrapezoidalRuleWithoutDissipation) {
  std::vector<double> ga, trap;
  const double drift = energy_drift({"generalized-alpha", {{"rho_inf", 1.0}}}, &ga);
  energy_drift({"trapezoidal", {}}, &trap);
  double worst = 0.0;
  for (size_t i = 0; i < ga.size(); ++i) worst = std::max(worst, std::abs(ga[i] - trap[i]));
  std::printf("  generalized-alpha rho_inf=1: max |E - E0| / E0 = %.3e, max |x - x_trap| = %.3e\n",
              drift, worst);
  EXPECT_LE(drift, 1e4 * 1e-15);
  EXPECT_LE(worst, 1e-10);

  Integrator a("generalized-alpha", {{"rho_inf", 1.0}}), t("trapezoidal");
  for (Integrator* i : {&a, &t}) {
    ASSERT_EQ(i->setup({MH_UNKNOWN_SECOND_ORDER, MH_UNKNOWN_FIRST_ORDER}, 0.0, 0.01), MH_OK);
    ASSERT_EQ(i->restart(0.0, {0.7, 3.0}, {-0.2, 1.5}, {4.0, 0.0}), MH_OK);
    ASSERT_EQ(i->begin_step(0.01, 0.01), MH_OK);
  }
  EXPECT_DOUBLE_EQ(a.map.coefficients.dxd_dx_second, t.map.coefficients.dxd_dx_second);
  EXPECT_DOUBLE_EQ(a.map.coefficients.dxdd_dx_second, t.map.coefficients.dxdd_dx_second);
  EXPECT_DOUBLE_EQ(a.map.coefficients.dxd_dx_first, t.map.coefficients.dxd_dx_first);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(a.xd_offset[i], t.xd_offset[i], 1e-12 * std::abs(t.xd_offset[i]));
    EXPECT_NEAR(a.xdd_offset[i], t.xdd_offset[i], 1e-12 * std::abs(t.xdd_offset[i]) + 1e-300);
  }
}

// Below rho_inf = 1 the method dissipates (here at h w = 0.1, where the
// dissipation is small but far above round-off).
TEST(GeneralizedAlpha, DissipatesBelowRhoInfOne) {
  for (double rho : {0.8, 0.5}) {
    const double drift = energy_drift({"generalized-alpha", {{"rho_inf", rho}}});
    std::printf("  generalized-alpha rho_inf=%.1f: energy lost over 1e4 steps: %.3e\n", rho, drift);
    EXPECT_GE(drift, 1e-6);
  }
}

TEST(GeneralizedAlpha, RefusesRhoInfOutsideZeroToOneThroughOptionError) {
  for (double bad : {2.0, -0.1, std::nan("")}) {
    Integrator integ("generalized-alpha", {{"rho_inf", bad}});
    EXPECT_EQ(integ.setup({MH_UNKNOWN_SECOND_ORDER}, 0.0, 0.01), MH_ERROR) << bad;
    ASSERT_EQ(integ.host.option_errors.size(), 1u) << bad;
    EXPECT_EQ(integ.host.option_errors[0], "rho_inf");
  }
  Integrator fine("generalized-alpha");
  EXPECT_EQ(fine.setup({MH_UNKNOWN_SECOND_ORDER}, 0.0, 0.01), MH_OK);
  EXPECT_TRUE(fine.host.option_errors.empty());
  EXPECT_EQ(fine.host.asked, std::vector<std::string>{"rho_inf"});  // read at setup, by name
}

}  // namespace
}  // namespace mh_test
