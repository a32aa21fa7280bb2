// A plugin built against a frozen copy of an earlier minor's headers alone
// loads in this host and runs as its equations say: the one source
// tests/fixtures/frozen_sdk_spring.c, built against tests/abi/sdk-3.0 and
// tests/abi/sdk-3.2 (the host reads each table up to the struct_size its
// plugin was built with, docs/sdk.md "Versioning: one rule").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {
namespace {

constexpr double kMass = 2.0;        // kg
constexpr double kStiffness = 50.0;  // N/m
constexpr double kStart = 0.1;       // m

// A slider on the x axis held at the origin by the spring `type`, released
// from x = 0.1 m at rest, no gravity: x(t) = 0.1 cos(sqrt(k/m) t).
std::string slider(const std::string& type) {
  return R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 2, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0.1}
subsystems:
  - name: holder
    type: )" +
         type +
         R"(
    points:
      a: {body: slider, at: [0, 0, 0]}
      b: {body: ground, at: [0, 0, 0]}
    stiffness: 50
formulation: open-loop
integrator: trapezoidal
solver: {dt: 0.001, t_end: 1}
)";
}

const PluginRegistry& frozen_and_shipped() {
  static const PluginRegistry* r = [] {
    auto* out = new PluginRegistry;
    out->scan({test::paths::frozen_sdk_plugin_dir, test::paths::plugin_dir});
    return out;
  }();
  return *r;
}

TEST(FrozenSdkPlugins, TheRegistryLoadsThe30And32BuildsNamingTheMinorEachWasBuiltWith) {
  const PluginRegistry& r = frozen_and_shipped();
  EXPECT_TRUE(r.refusals().empty()) << r.refusals().front();
  const ComponentInfo& old = r.find(ComponentKind::subsystem, "sdk30-spring");
  const ComponentInfo& recent = r.find(ComponentKind::subsystem, "sdk32-spring");
  EXPECT_EQ(old.abi_version.major, 3u);
  EXPECT_EQ(old.abi_version.minor, 0u);
  EXPECT_EQ(recent.abi_version.major, 3u);
  EXPECT_EQ(recent.abi_version.minor, 2u);
  EXPECT_LE(recent.abi_version.minor, static_cast<uint32_t>(MH_ABI_VERSION_MINOR));
}

TEST(FrozenSdkPlugins, BothBuildsRunTheSliderAsItsClosedFormAndAsEachOtherToTheBit) {
  const double omega = std::sqrt(kStiffness / kMass);
  std::vector<std::vector<double>> paths;
  for (const char* type : {"sdk30-spring", "sdk32-spring"}) {
    const ModelFile file = parse_model_text(slider(type), "slider.yaml");
    Simulation sim(file, frozen_and_shipped());
    const int stretch = sim.output_index("holder.stretch");
    ASSERT_GE(stretch, 0) << type;
    sim.start();
    std::vector<double> path;
    double worst = 0.0;
    while (sim.time() < 1.0 - 1e-9) {
      sim.step();
      const double x = sim.z()[0];
      path.push_back(x);
      worst = std::max(worst, std::abs(x - kStart * std::cos(omega * sim.time())));
      EXPECT_NEAR(sim.outputs()[stretch], std::abs(x), 1e-15) << type << " at " << sim.time();
    }
    // The trapezoidal rule keeps the amplitude and lags the phase by
    // omega^3 dt^2 t / 12 (1e-5 rad after 1 s): 1e-6 m at most.
    EXPECT_LT(worst, 2e-6) << type;
    EXPECT_EQ(path.size(), 1000u) << type;
    paths.push_back(path);
  }
  EXPECT_EQ(paths[0], paths[1]);  // the same source, built against either minor
}

}  // namespace
}  // namespace mh
