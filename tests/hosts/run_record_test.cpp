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

// A valve section names where its dissipation happens (outputs of role
// dissipation-part): its meter-in and meter-out edges, its compensator and its
// load-sense orifices, integrated as the sections' whole; they add up to it.
TEST(RunRecord, AValveSectionsDissipationPartsAddUpToItsDissipation) {
  const ModelFile file = load_model_file(source_path("models/excavator-ls.yaml"));
  cli::RecordOptions options;
  options.overrides.t_end = 3.0;
  const cli::RunRecord rec = cli::record_run(file, build_plugins(), "", "", options);
  ASSERT_FALSE(rec.failed) << rec.failure;
  ASSERT_EQ(rec.parts_dissipated.size(), rec.dissipation_parts.size());
  ASSERT_EQ(rec.dissipation_parts.size(), 16u);  // four sections, four parts each
  for (const std::string section : {"valve_boom", "valve_arm", "valve_bucket", "valve_slew"}) {
    const auto it = std::find(rec.dissipators.begin(), rec.dissipators.end(), section);
    ASSERT_NE(it, rec.dissipators.end()) << section;
    const double whole = rec.dissipated[static_cast<size_t>(it - rec.dissipators.begin())];
    double sum = 0.0, compensator = 0.0, meter_in = 0.0;
    for (size_t j = 0; j < rec.dissipation_parts.size(); ++j) {
      const std::string& part = rec.dissipation_parts[j];
      if (part.rfind(section + ".", 0) != 0) continue;
      sum += rec.parts_dissipated[j];
      if (part == section + ".P_compensator") compensator = rec.parts_dissipated[j];
      if (part == section + ".P_meter_in") meter_in = rec.parts_dissipated[j];
    }
    EXPECT_NEAR(sum, whole, 1e-9 * std::max(whole, 1.0)) << section;
    EXPECT_GE(compensator, 0.0) << section;  // it only ever takes pressure away
    if (section == "valve_boom") {           // lowered in these 3 s: its edge throttles (J)
      EXPECT_GT(meter_in, 1e3);
    }
    if (section ==
        "valve_arm") {  // it moves beside the boom's higher load: its compensator throttles
      EXPECT_GT(compensator, 100.0);
    }
  }
}

}  // namespace
}  // namespace mh::test
