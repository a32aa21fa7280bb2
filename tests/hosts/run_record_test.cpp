// A run kept in memory (hosts/monohydra/run_record.cpp): the breakdown of the
// dissipated energy by subsystem, which the report's "where the energy goes"
// draws, adds up to the energy balance's own dissipated energy.
#include "run_record.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

// The load-sensing excavator's first 3 s: every valve section, the pump, the
// counterbalance valves and the cylinders dissipate.
TEST(RunRecord, TheDissipationOfEachSubsystemAddsUpToTheRunsDissipatedEnergy) {
  const ModelFile file = load_model_file(source_path("models/excavator-ls.yaml"));
  cli::RecordOptions options;
  options.overrides.t_end = 3.0;
  const cli::RunRecord rec = cli::record_run(file, build_plugins(), "", "", options);
  ASSERT_FALSE(rec.failed) << rec.failure;

  Simulation sim(file, build_plugins(), RunChoices{"", "", {}, 3.0});
  sim.start();
  while (sim.time() < 3.0 - 0.5e-3) sim.step();

  ASSERT_EQ(rec.dissipators, sim.subsystem_names());
  ASSERT_EQ(rec.dissipated.size(), rec.dissipators.size());
  const double total = std::accumulate(rec.dissipated.begin(), rec.dissipated.end(), 0.0);
  EXPECT_GT(sim.dissipated_energy(), 1e4);  // J: a few tens of kJ in 3 s
  EXPECT_NEAR(total, sim.dissipated_energy(), 1e-9 * sim.dissipated_energy());
  for (size_t i = 0; i < rec.dissipated.size(); ++i)
    EXPECT_GE(rec.dissipated[i], 0.0) << rec.dissipators[i];
  auto of = [&](const std::string& name) {
    const auto it = std::find(rec.dissipators.begin(), rec.dissipators.end(), name);
    return it == rec.dissipators.end() ? -1.0 : rec.dissipated[it - rec.dissipators.begin()];
  };
  EXPECT_GT(of("pump"), 0.0);  // its leakage
  EXPECT_GT(of("valve_boom"), 0.0);
}

}  // namespace
}  // namespace mh::test
