// A plugin built by a third party against the installed SDK alone (in C, see
// sdk/examples/point-load) loads and does physics: a constant force on a free
// slider gives x = F t^2 / (2 m), which the trapezoidal rule integrates exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {
namespace {

const char* kSlider = R"(
units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - name: slider
    parent: ground
    joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]}
    mass: 4.0
    com: [0, 0, 0]
    inertia: [1, 1, 1]
subsystems:
  - name: push
    type: point-load
    points: {at: {body: slider, at: [0, 0.5, 0]}}
    force: [10, 3, 0]
formulation: open-loop
solver: {dt: 0.01, t_end: 2}
)";

TEST(InstalledSdkPlugin, ThirdPartyCPluginLoadsAndMovesASliderExactly) {
  PluginRegistry registry;
  registry.load(std::string(mh::test::paths::sdk_example_dir) + "/point-load.so");
  registry.scan({mh::test::paths::plugin_dir});
  const ComponentInfo& info = registry.find(ComponentKind::subsystem, "point-load");
  EXPECT_EQ(std::string(info.descriptor->vendor), "example.org");
  const ModelFile file = parse_model_text(kSlider, "slider.yaml");
  Simulation sim(file, registry);
  const RunSummary s = run(sim, nullptr);
  ASSERT_FALSE(s.failed) << s.failure;
  const double t = sim.time();
  EXPECT_NEAR(sim.z()[0], 10.0 * t * t / (2.0 * 4.0), 1e-10);  // only F_x acts along the axis
  EXPECT_NEAR(sim.work(), sim.kinetic_energy(), 1e-8);         // W = KE: no other force
}

}  // namespace
}  // namespace mh
