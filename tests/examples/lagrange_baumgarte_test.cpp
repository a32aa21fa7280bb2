// The example formulation examples/lagrange-baumgarte, built against the
// installed SDK alone (build_examples.cmake), on the paper's four-bar: it
// follows double-step, its multipliers are the constraint forces the penalty
// formulation's augmented Lagrangian converges to, its analytic tangent equals
// differences, Baumgarte's terms keep the loop closed where plain index-1
// multipliers let it open, and redundant constraints are refused clearly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "build_paths.hpp"
#include "monohydra/constrained.h"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// The build's plugins and the example lagrange-baumgarte.
const PluginRegistry& plugins() {
  return test::build_plugins_with(std::string(mh::test::paths::examples_dir) +
                                  "/lagrange-baumgarte/lagrange-baumgarte.so");
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A shipped model with its formulation line replaced by `formulation`.
ModelFile with_formulation(const std::string& model, const std::string& from,
                           const std::string& formulation) {
  std::string text = read(test::source_path("models/" + model));
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << model << " has no '" << from << "'";
  text.replace(at, from.size(), formulation);
  return parse_model_text(text, model, test::source_path("models"));
}

Simulation& run_to(Simulation& sim, double t) {
  while (sim.time() < t - 1e-9) sim.step();
  return sim;
}

TEST(LagrangeBaumgarte, FollowsDoubleStepOnTheFourBarWithTheLoopClosed) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation lb(file, plugins(), RunChoices{"lagrange-baumgarte", "", std::nullopt, 3.0});
  Simulation ds(file, plugins(), RunChoices{"double-step", "", std::nullopt, 3.0});
  lb.start();
  ds.start();
  double max_dz = 0.0, max_phi = 0.0, max_drift = 0.0;
  while (lb.time() < 3.0 - 1e-9) {
    lb.step();
    ds.step();
    max_dz = std::max(max_dz, (lb.z() - ds.z()).lpNorm<Eigen::Infinity>());
    max_phi = std::max(max_phi, lb.phi_norm());
    max_drift = std::max(max_drift, std::abs(lb.drift() - ds.drift()));
  }
  EXPECT_LT(max_dz, 1e-6);     // rad
  EXPECT_LT(max_phi, 1e-6);    // the Baumgarte terms keep Phi small ...
  EXPECT_GT(max_phi, 1e-13);   // ... but do not remove it: no projections
  EXPECT_LT(max_drift, 1e-3);  // J: the same energy balance
}

TEST(LagrangeBaumgarteMultipliers, AreThePenaltyFormulationsConstraintForces) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation lb(file, plugins(), RunChoices{"lagrange-baumgarte", "", std::nullopt, 2.0});
  Simulation pen(file, plugins(), RunChoices{"penalty", "", std::nullopt, 2.0});
  lb.start();
  pen.start();
  run_to(lb, 2.0);
  run_to(pen, 2.0);
  for (const char* name : {"lambda1", "lambda2"}) {
    const int ia = lb.output_index(std::string("lagrange-baumgarte.") + name);
    const int ib = pen.output_index(std::string("penalty.") + name);
    ASSERT_GE(ia, 0) << name;
    ASSERT_GE(ib, 0) << name;
    const double a = lb.outputs()[ia], b = pen.outputs()[ib];
    EXPECT_GT(std::abs(b), 10.0) << name;  // N: a real constraint force
    EXPECT_NEAR(a, b, 1e-3 * std::abs(b)) << name;
  }
}

// On the free four-bar: with a subsystem on body points (the cylinder) this
// host differences every mechanical column whatever the formulation gives
// (docs/sdk.md, tangent), so the analytic blocks are only used, and tested,
// without one.
TEST(LagrangeBaumgarte, AnalyticTangentEqualsForwardDifferences) {
  const ModelFile file = with_formulation("fourbar-free.yaml", "formulation: {name: double-step}",
                                          "formulation: {name: lagrange-baumgarte}");
  Simulation sim(file, plugins());
  sim.start();
  run_to(sim, 0.5);  // falling, with velocities
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_fd = sim.finite_difference_tangent();
  ASSERT_EQ(J.rows(), 5);  // z1..z3, lambda1, lambda2
  EXPECT_LT((J - J_fd).norm(), 1e-6 * J_fd.norm()) << "analytic\n"
                                                   << J << "\ndifferences\n"
                                                   << J_fd;
}

// The free four-bar at dt = 10 ms: without stabilization (alpha = beta = 0)
// the index-1 constraint drifts and the loop opens; Baumgarte's terms hold it.
double max_phi_on_free_fourbar(const std::string& options) {
  const ModelFile file = with_formulation("fourbar-free.yaml", "formulation: {name: double-step}",
                                          "formulation: {name: lagrange-baumgarte" + options + "}");
  Simulation sim(file, plugins(), RunChoices{"", "", 1e-2, 10.0});
  sim.start();
  double max_phi = 0.0;
  while (sim.time() < 10.0 - 1e-9) {
    sim.step();
    max_phi = std::max(max_phi, sim.phi_norm());
  }
  return max_phi;
}

TEST(LagrangeBaumgarte, StabilizationKeepsTheLoopClosedWhereIndexOneDrifts) {
  const double plain = max_phi_on_free_fourbar(", alpha: 0, beta: 0");
  const double stabilized = max_phi_on_free_fourbar("");
  RecordProperty("phi_plain", test::scientific(plain));
  RecordProperty("phi_baumgarte", test::scientific(stabilized));
  EXPECT_GT(plain, 5.0 * stabilized);  // measured: 2.1e-4 against 2.9e-5 rad
}

TEST(LagrangeBaumgarte, RedundantConstraintsAreRefusedNamingTheCause) {
  const ModelFile file =
      with_formulation("parallelogram-redundant.yaml", "formulation: {name: penalty}",
                       "formulation: {name: lagrange-baumgarte}");
  std::string err;
  try {
    Simulation sim(file, plugins());
    sim.start();
  } catch (const std::exception& e) {
    err = e.what();
  }
  EXPECT_NE(err.find("redundant"), std::string::npos) << err;
}

// It copies z0 at setup and does not declare MH_EXT_INITIAL_STATE_AT_START:
// an initial coordinate as a sensitivity's parameter is refused, naming the
// formulation and the extension, where one of its mass is taken.
TEST(LagrangeBaumgarte, RefusesAnInitialCoordinateAsASensitivityParameter) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, plugins(), RunChoices{"lagrange-baumgarte", "", std::nullopt, 0.1});
  ParameterDirection angle;
  angle.path = "bodies/body1/z0";
  angle.initial.push_back({0, 1.0, 0.0});
  try {
    sim.track_sensitivities({angle});
    ADD_FAILURE() << "an initial coordinate was taken";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("lagrange-baumgarte"), std::string::npos) << what;
    EXPECT_NE(what.find(MH_EXT_INITIAL_STATE_AT_START), std::string::npos) << what;
  }
  ParameterDirection mass;
  mass.path = "bodies/body3/mass";
  mass.value = file.model.bodies[2].mass;
  mass.bodies.push_back({2, 1.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero()});
  EXPECT_NO_THROW(sim.track_sensitivities({mass}));
}

}  // namespace
}  // namespace mh
