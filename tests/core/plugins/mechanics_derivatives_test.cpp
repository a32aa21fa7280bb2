// The host service mech_derivatives (core/src/plugins/components/mechanics_derivatives.cpp): K and
// C of the full dynamics, subsystem forces included through their point-force
// derivatives, against central differences of M' zdd - Q' with the same
// subsystems at the same states. Models with a hydraulic cylinder (the
// paper's case studies) and a spring-damper-like Maxwell element.
#include <gtest/gtest.h>

#include <random>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

struct Fd {
  Eigen::MatrixXd K, C;
};

// Central differences of M' zdd - Q' in z and zd.
Fd differences(Simulation& sim, const Eigen::VectorXd& z, const Eigen::VectorXd& zd,
               const Eigen::VectorXd& zdd) {
  const Eigen::Index N = z.size();
  Fd out{Eigen::MatrixXd(N, N), Eigen::MatrixXd(N, N)};
  for (Eigen::Index k = 0; k < N; ++k) {
    for (int level = 0; level < 2; ++level) {
      Eigen::VectorXd zp = z, zm = z, zdp = zd, zdm = zd;
      const double h = 1e-6;
      (level == 0 ? zp : zdp)[k] += h;
      (level == 0 ? zm : zdm)[k] -= h;
      const Eigen::VectorXd d =
          (sim.dynamics_residual(zp, zdp, zdd) - sim.dynamics_residual(zm, zdm, zdd)) / (2 * h);
      (level == 0 ? out.K : out.C).col(k) = d;
    }
  }
  return out;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

void expect_match_at_random_states(const std::string& model, int steps_first) {
  const ModelFile file = load_model_file(source_path("models/" + model));
  Simulation sim(file, build_plugins());
  sim.start();
  for (int k = 0; k < steps_first; ++k) sim.step();  // pressures and forces away from rest
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_k = 0.0, worst_c = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd z = sim.z(), zd = sim.zd(), zdd = sim.zdd();
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      z[i] += 0.01 * u(rng);  // near the state: the cylinder stays within its stroke
      zd[i] += 0.5 * u(rng);
      zdd[i] += 5.0 * u(rng);
    }
    const auto d = sim.mechanics_derivatives(z, zd, zdd);
    const Fd fd = differences(sim, z, zd, zdd);
    worst_k = std::max(worst_k, relative(d.K, fd.K));
    worst_c = std::max(worst_c, relative(d.C, fd.C));
    EXPECT_GT(fd.K.lpNorm<Eigen::Infinity>(), 0.0);
  }
  ::testing::Test::RecordProperty("worst_relative_K", scientific(worst_k));
  ::testing::Test::RecordProperty("worst_relative_C", scientific(worst_c));
  EXPECT_LT(worst_k, 1e-6) << model;
  EXPECT_LT(worst_c, 1e-6) << model;
}

TEST(MechanicsDerivatives, StiffnessAndDampingWithTheCylinderMatchDifferencesOnTheFourBar) {
  expect_match_at_random_states("fourbar.yaml", 1500);  // inside the valve's first opening
}

TEST(MechanicsDerivatives, StiffnessAndDampingWithTheCylinderMatchDifferencesOnTheQuickReturn) {
  expect_match_at_random_states("quickreturn.yaml", 1500);
}

TEST(MechanicsDerivatives, StiffnessAndDampingWithAMaxwellElementMatchDifferences) {
  expect_match_at_random_states("maxwell-pendulum.yaml", 200);
}

// Without subsystems with points the service is the core's recursion alone:
// the gravity stiffness of a double pendulum.
TEST(MechanicsDerivatives, StiffnessOfATreeUnderGravityMatchesDifferences) {
  expect_match_at_random_states("double-pendulum.yaml", 100);
}

}  // namespace
}  // namespace mh::test
