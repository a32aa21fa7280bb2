// The load-sensing excavator (models/excavator-ls.yaml) with its bucket's
// edge in the ground (bucket-soil, docs/soil.md): the first 8 s of its cycle
// (arm in, boom down and bucket curl cut about 0.25 m deep and 1.4 m long
// towards the machine, then boom up) beside the same cycle in air. The
// soil loads the arm's cylinder in the same Newton step as the mechanics;
// double-step and penalty agree; the bodies' energy balance still closes.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "models/excavator_dig_model.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

struct CycleRun {
  std::vector<Eigen::VectorXd> z;
  std::vector<double> p_arm_a, p_bucket_a, fh, depth;
  double max_drift = 0.0, work = 0.0;
};

const CycleRun& run(bool digging, const std::string& formulation) {
  static std::map<std::pair<bool, std::string>, CycleRun> runs;
  const auto key = std::make_pair(digging, formulation);
  auto it = runs.find(key);
  if (it != runs.end()) return it->second;
  CycleRun& r = runs[key];
  const ModelFile file = parse_model_text(test::excavator_dig_model(digging), "excavator-dig.yaml");
  Simulation sim(file, test::build_plugins(), RunChoices{formulation, "", {}, {}});
  sim.start();
  const int arm = sim.state_index("p_arm_a"), bucket = sim.state_index("p_bucket_a");
  const int fh = sim.output_index("soil.Fh"), depth = sim.output_index("soil.depth");
  EXPECT_GE(arm, 0);
  EXPECT_GE(bucket, 0);
  while (sim.time() < 8.0 - 1e-9) {
    sim.step();
    r.z.push_back(sim.z());
    r.p_arm_a.push_back(sim.states()[arm]);
    r.p_bucket_a.push_back(sim.states()[bucket]);
    r.fh.push_back(fh < 0 ? 0.0 : sim.outputs()[fh]);
    r.depth.push_back(depth < 0 ? -1.0 : sim.outputs()[depth]);
    const double balance = sim.kinetic_energy() + sim.potential_energy() - sim.work();
    r.max_drift = std::max(r.max_drift, std::abs(balance));
    r.work = std::max(r.work, std::abs(sim.work()));
  }
  return r;
}

TEST(ExcavatorDig, TheBucketCutsIntoTheGroundAndTheSoilLoadsTheArmsCylinder) {
  const CycleRun& air = run(false, "double-step");
  const CycleRun& dig = run(true, "double-step");
  ASSERT_EQ(air.z.size(), dig.z.size());
  EXPECT_GT(*std::max_element(dig.depth.begin(), dig.depth.end()), 0.2);
  EXPECT_GT(*std::max_element(dig.fh.begin(), dig.fh.end()), 1e4);
  // Until the edge meets the ground the runs are the same (to the rounding of
  // a tangent with the soil's entries in it); during the cut
  // the arm's cap side (pulling the arm in) works against the soil.
  size_t first_cut = 0;
  while (first_cut < dig.depth.size() && dig.depth[first_cut] <= 0.0) ++first_cut;
  ASSERT_LT(first_cut, dig.depth.size());
  for (size_t i = 0; i < first_cut; ++i)
    ASSERT_LT((air.z[i] - dig.z[i]).cwiseAbs().maxCoeff(), 1e-10) << i;
  double rise = 0.0;
  for (size_t i = first_cut; i < dig.depth.size(); ++i)
    if (dig.depth[i] > 0.1) rise = std::max(rise, dig.p_arm_a[i] - air.p_arm_a[i]);
  EXPECT_GT(rise, 3e6);
  // The bodies' balance: kinetic + potential energy = the work of every
  // subsystem's force on them, the soil's among them.
  EXPECT_LT(dig.max_drift, 1e-5 * dig.work);
}

TEST(ExcavatorDig, DoubleStepAndPenaltyAgreeWhileTheBucketDigs) {
  const CycleRun& a = run(true, "double-step");
  const CycleRun& b = run(true, "penalty");
  ASSERT_EQ(a.z.size(), b.z.size());
  double dz = 0.0, dp = 0.0;
  for (size_t i = 0; i < a.z.size(); ++i) {
    dz = std::max(dz, (a.z[i] - b.z[i]).cwiseAbs().maxCoeff());
    dp = std::max(
        {dp, std::abs(a.p_arm_a[i] - b.p_arm_a[i]), std::abs(a.p_bucket_a[i] - b.p_bucket_a[i])});
  }
  std::printf("double-step against penalty: %.3g rad, %.3g Pa\n", dz, dp);
  EXPECT_LT(dz, 1e-5);  // rad
  EXPECT_LT(dp, 10e3);  // Pa
}

}  // namespace
}  // namespace mh
