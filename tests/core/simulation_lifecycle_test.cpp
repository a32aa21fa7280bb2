// What a Simulation's user may and may not do with it: it reads its model
// file for as long as it lives (a temporary is refused at compile time: it
// crashed so), and it starts once (a second start would go on from the last
// accepted state, not from t = 0, and is refused).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

// A pendulum on a revolute joint: the smallest model that runs.
constexpr const char* kPendulum = R"(units: {length: m, mass: kg, time: s, angle: deg}
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},
     mass: 1, shape: {type: beam, length: 1}, z0: -60}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

TEST(SimulationLifecycle, ATemporaryModelFileIsRefusedAtCompileTime) {
  static_assert(
      !std::is_constructible_v<Simulation, ModelFile&&, const PluginRegistry&, const RunChoices&>);
  static_assert(!std::is_constructible_v<Simulation, ModelFile&&, const PluginRegistry&>);
  EXPECT_TRUE((std::is_constructible_v<Simulation, const ModelFile&, const PluginRegistry&,
                                       const RunChoices&>));
}

TEST(SimulationLifecycle, ASecondStartIsRefusedNamingTheTimeAndStepAndTheFirstRunIsKept) {
  const ModelFile file = parse_model_text(kPendulum, "pendulum.yaml");
  Simulation sim(file, test::build_plugins());
  sim.start();
  for (int k = 0; k < 5; ++k) sim.step();
  const double t = sim.time();
  try {
    sim.start();
    FAIL() << "a second start() was accepted";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("already started"), std::string::npos) << what;
  }
  EXPECT_EQ(sim.time(), t);  // the run so far is untouched and goes on
  sim.step();
  EXPECT_GT(sim.time(), t);
}

TEST(SimulationLifecycle, RunsSharingTheirFixedPartsStepAsTheirOwnWouldToTheBit) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  const PluginRegistry& plugins = test::build_plugins();
  Simulation first(file, plugins), sharing(file, plugins), alone(file, plugins);
  EXPECT_TRUE(sharing.share_fixed_parts(first));
  EXPECT_EQ(&sharing.tangent_pattern(), &first.tangent_pattern());  // one pattern
  EXPECT_NE(&alone.tangent_pattern(), &first.tangent_pattern());
  for (Simulation* s : {&first, &sharing, &alone}) s->start();
  for (int k = 0; k < 1500; ++k) {  // through the valve's opening at 1 s
    sharing.step();
    alone.step();
  }
  EXPECT_EQ(sharing.z(), alone.z());
  EXPECT_EQ(sharing.states(), alone.states());
  // Another pattern is not taken (a pendulum's); a started run takes none.
  const ModelFile other = parse_model_text(kPendulum, "pendulum.yaml");
  Simulation pendulum(other, plugins);
  EXPECT_FALSE(pendulum.share_fixed_parts(first));
  EXPECT_NE(&pendulum.tangent_pattern(), &first.tangent_pattern());
  EXPECT_THROW(alone.share_fixed_parts(first), std::invalid_argument);
}

}  // namespace
}  // namespace mh
