// A plugin of an older minor version on the current host: tests/fixtures/
// sdk20_spring.c is built against the frozen SDK 2.0 headers
// (tests/abi/sdk-2.0) and runs on this 2.1 host. Its subsystem table ends
// before 2.1's point_force_jacobian; the host reads it only up to its
// struct_size, takes the missing op as NULL and differences instead.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

const PluginRegistry& registry_with_sdk20_plugin() {
  static const PluginRegistry* r = [] {
    auto* reg = new PluginRegistry;
    reg->scan({MH_PLUGIN_DIR, MH_SDK20_PLUGIN_DIR});
    return reg;
  }();
  return *r;
}

// The double pendulum with its tip tied to the ground point (1, -1) by the
// 2.0 spring, started from rest with both links horizontal.
ModelFile spring_pendulum() {
  return parse_model_text(
      "units: {length: m, mass: kg, time: s, angle: deg}\n"
      "bodies:\n"
      "  - {name: link1, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},"
      " mass: 1.0, shape: {type: beam, length: 1.0}}\n"
      "  - {name: link2, parent: link1, joint: {type: revolute, at: [1, 0, 0], axis: [0, 0, 1]},"
      " mass: 1.0, shape: {type: beam, length: 1.0}}\n"
      "subsystems:\n"
      "  - name: spring\n"
      "    type: sdk20-spring\n"
      "    stiffness: 40\n"
      "    points: {a: {body: link2, at: [1, 0, 0]}, b: {body: ground, at: [1, -1, 0]}}\n"
      "formulation: open-loop\n"
      "solver: {dt: 0.001, t_end: 3}\n",
      "spring-pendulum.yaml");
}

TEST(OldMinorPlugin, AnSdk20PluginLoadsOnThisHostWithItsOwnVersion) {
  const PluginRegistry& r = registry_with_sdk20_plugin();
  const ComponentInfo& c = r.find(ComponentKind::subsystem, "sdk20-spring");
  EXPECT_EQ(c.abi_version.major, 2u);
  EXPECT_EQ(c.abi_version.minor, 0u);
  EXPECT_LT(MH_ABI_VERSION_MINOR, 100u);
  EXPECT_GT(MH_ABI_VERSION_MINOR, c.abi_version.minor) << "the host is of a later minor version";
  EXPECT_TRUE(r.refusals().empty());
}

// Energy is conserved to the trapezoidal rule's accuracy: the spring's work on
// the bodies is minus the change of its stored energy, and KE + PE + stored
// stays put over 3 s of a chaotic swing.
TEST(OldMinorPlugin, AnSdk20SpringRunsOnThisHostAndConservesEnergy) {
  const ModelFile file = spring_pendulum();
  Simulation sim(file, registry_with_sdk20_plugin());
  const RunSummary s = run(sim, nullptr);
  ASSERT_FALSE(s.failed) << s.failure;
  EXPECT_EQ(s.steps, 3000);
  const double total = sim.kinetic_energy() + sim.potential_energy() + sim.stored_energy();
  const double scale = std::abs(sim.potential_energy()) + sim.kinetic_energy();
  ::testing::Test::RecordProperty("energy_error", scientific(total));
  EXPECT_GT(scale, 1.0);  // it did swing
  EXPECT_LT(std::abs(total), 1e-3 * scale);
  EXPECT_NEAR(sim.work(), -sim.stored_energy(), 1e-3 * scale);
  // Its 2.0 output reached the results.
  const int stretch = sim.output_index("spring.stretch");
  ASSERT_GE(stretch, 0);
  EXPECT_GT(sim.outputs()[stretch], 0.0);
}

// 2.1's mech_derivatives on a 2.0 subsystem: its point forces are differenced
// (it has no point_force_jacobian), and K, C still match differences of the
// whole dynamics.
TEST(OldMinorPlugin, MechanicsDerivativesDifferenceTheSdk20SpringsForces) {
  const ModelFile file = spring_pendulum();
  Simulation sim(file, registry_with_sdk20_plugin());
  sim.start();
  for (int k = 0; k < 100; ++k) sim.step();
  const Eigen::VectorXd z = sim.z(), zd = sim.zd(), zdd = sim.zdd();
  const auto d = sim.mechanics_derivatives(z, zd, zdd);
  Eigen::MatrixXd K(2, 2);
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd zp = z, zm = z;
    zp[k] += 1e-6;
    zm[k] -= 1e-6;
    K.col(k) = (sim.dynamics_residual(zp, zd, zdd) - sim.dynamics_residual(zm, zd, zdd)) / 2e-6;
  }
  EXPECT_LT((d.K - K).lpNorm<Eigen::Infinity>(), 1e-6 * K.lpNorm<Eigen::Infinity>());
  EXPECT_GT(K.lpNorm<Eigen::Infinity>(), 40.0 * 0.5);  // the spring's 40 N/m shows
}

// 2.4 appended mh_subsystem_factory.example_model. A plugin built against
// SDK 2.3 (tests/fixtures/faulty/faulty_spring.c as SDK23_FACTORY: its
// factory's struct_size ends before the field, its entry says 2.3) loads with
// its own version, reads as declaring no example model, and runs; so does the
// 2.0 spring, whose factory is older still.
TEST(OldMinorPlugin, AnSdk23SubsystemLoadsReadsNoExampleModelAndRuns) {
  PluginRegistry r;
  r.load(std::string(MH_CHECK_FIXTURE_DIR) + "/sdk23_spring.so");
  r.scan({MH_PLUGIN_DIR});
  const ComponentInfo& c = r.find(ComponentKind::subsystem, "faulty-spring");
  EXPECT_EQ(c.abi_version.major, 2u);
  EXPECT_EQ(c.abi_version.minor, 3u);
  EXPECT_EQ(c.subsystem_factory.struct_size, offsetof(mh_subsystem_factory, example_model));
  EXPECT_EQ(c.subsystem_factory.example_model, nullptr);
  const ComponentInfo& old =
      registry_with_sdk20_plugin().find(ComponentKind::subsystem, "sdk20-spring");
  EXPECT_EQ(old.subsystem_factory.example_model, nullptr);

  ModelFile file = load_model_file(source_path("tests/fixtures/check/spring-pendulum.yaml"));
  Simulation sim(file, r, RunChoices{"", "", std::nullopt, 0.5});
  const RunSummary s = run(sim, nullptr);
  ASSERT_FALSE(s.failed) << s.failure;
  EXPECT_EQ(s.steps, 500);
  EXPECT_GT(sim.kinetic_energy(), 0.1);  // J: it swung
}

}  // namespace
}  // namespace mh::test
