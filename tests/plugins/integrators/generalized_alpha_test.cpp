// The generalized-alpha method: its dissipation is what rho_inf asks for.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <complex>
#include <cstdio>

#include "problems.hpp"

namespace mh_test {
namespace {

using Sequence = std::vector<std::array<double, 2>>;  // (x_n, scaled xd_n), n = 1, 2, ...

// The roots of l^m - c[0] l^(m-1) - ... - c[m-1] (Durand-Kerner).
std::vector<std::complex<double>> roots(const std::vector<double>& c) {
  using C = std::complex<double>;
  const size_t m = c.size();
  std::vector<C> r(m);
  for (size_t i = 0; i < m; ++i) r[i] = std::pow(C(0.4, 0.9), static_cast<double>(i + 1));
  const auto poly = [&](C l) {
    C v = 1.0;
    for (double ci : c) v = v * l - ci;
    return v;
  };
  for (int it = 0; it < 500; ++it)
    for (size_t i = 0; i < m; ++i) {
      C d = 1.0;
      for (size_t j = 0; j < m; ++j)
        if (j != i) d *= r[i] - r[j];
      r[i] -= poly(r[i]) / d;
    }
  return r;
}

// The spectral radius of a linear step measured from the sequence of its
// observables: with a state of m numbers, every observable obeys (Cayley-
// Hamilton) s_{n+m} = c[0] s_{n+m-1} + ... + c[m-1] s_n with the
// characteristic polynomial's coefficients, which are fitted by least squares
// (each equation normalised); the radius is the largest root. A mode the
// observables do not see (rank-deficient fit) is dropped by fitting m - 1.
double recurrence_radius(const Sequence& seq, size_t m) {
  for (; m > 0; --m) {
    std::vector<double> N(m * m, 0.0), b(m, 0.0);
    for (size_t n = 0; n + m < seq.size(); ++n)
      for (size_t k = 0; k < 2; ++k) {
        std::vector<double> row(m);
        double big = 1e-300;
        for (size_t i = 0; i < m; ++i)
          big = std::max(big, std::abs(row[i] = seq[n + m - 1 - i][k]));
        for (size_t i = 0; i < m; ++i) {
          for (size_t j = 0; j < m; ++j) N[i * m + j] += row[i] * row[j] / (big * big);
          b[i] += row[i] * seq[n + m][k] / (big * big);
        }
      }
    // Rank check: Cholesky pivots of the normal equations relative to their diagonal.
    std::vector<double> L = N;
    bool full_rank = true;
    for (size_t j = 0; j < m && full_rank; ++j) {
      double d = L[j * m + j];
      for (size_t k = 0; k < j; ++k) d -= L[j * m + k] * L[j * m + k];
      if (!(d > 1e-12 * N[j * m + j])) full_rank = false;
      d = std::sqrt(d);
      L[j * m + j] = d;
      for (size_t i = j + 1; i < m; ++i) {
        double v = L[i * m + j];
        for (size_t k = 0; k < j; ++k) v -= L[i * m + k] * L[j * m + k];
        L[i * m + j] = v / d;
      }
    }
    if (!full_rank) continue;
    solve_dense(N, b);
    double radius = 0.0;
    for (const auto& r : roots(b)) radius = std::max(radius, std::abs(r));
    return radius;
  }
  return 0.0;
}

// The spectral radius of the step on x'' + w^2 x = 0 at h w = hw: its state
// is (x, xd, a) (xdd = -w^2 x is enforced), 3 numbers. The restart's
// xdd_0 = a_0 is off the free response so that every mode is excited; s_0 is
// then outside the step's invariant state space and is not recorded.
double spectral_radius(const std::map<std::string, double>& options, double hw, int steps) {
  const double w = hw;  // h = 1
  const LinearProblem p{
      {MH_UNKNOWN_SECOND_ORDER}, {1.0}, {0.0}, {w * w}, [](double, double* f) { f[0] = 0.0; }};
  Sequence seq;
  Integrator integ("generalized-alpha", options);
  run(integ, p, State{0.0, {1.0}, {0.3 * w}, {-0.5 * w * w}},
      std::vector<double>(static_cast<size_t>(steps), 1.0), [&](const State& s) {
        seq.push_back({s.x[0], s.xd[0] / w});
      });
  return recurrence_radius(seq, 3);
}

// The same for first-order unknowns, y' = lambda y at h lambda = -hl: the
// state is (y, v), 2 numbers; v_0 = yd_0 is off the free response.
double first_order_spectral_radius(double rho, double hl, int steps) {
  const double lambda = -hl;  // h = 1
  const LinearProblem p{
      {MH_UNKNOWN_FIRST_ORDER}, {0.0}, {1.0}, {-lambda}, [](double, double* f) { f[0] = 0.0; }};
  Sequence seq;
  Integrator integ("generalized-alpha", {{"rho_inf", rho}});
  run(integ, p, State{0.0, {1.0}, {0.5 * lambda}, {0.0}},
      std::vector<double>(static_cast<size_t>(steps), 1.0), [&](const State& s) {
        seq.push_back({s.x[0], s.xd[0] / hl});
      });
  return recurrence_radius(seq, 2);
}

TEST(GeneralizedAlpha, SpectralRadiusAtInfinityIsRhoInf) {
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    const double measured = spectral_radius({{"rho_inf", rho}}, 1e6, 8);
    std::printf("  generalized-alpha rho_inf=%.1f: spectral radius at h w = 1e6: %.6f\n", rho,
                measured);
    EXPECT_NEAR(measured, rho, 1e-3) << "rho_inf = " << rho;
  }
}

TEST(GeneralizedAlpha, FirstOrderSpectralRadiusAtInfinityIsRhoInf) {
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    const double measured = first_order_spectral_radius(rho, 1e6, 8);
    std::printf(
        "  generalized-alpha rho_inf=%.1f: first-order spectral radius at h lambda = -1e6: "
        "%.6f\n",
        rho, measured);
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
