// open-centre-valve (docs/hydraulics.md): in a run of its example (a fixed
// 0.1 l/s pump, an 8 MPa load) the neutral centre holds the pump at tank +
// the bypass drop, the opened valve at the load + the working edge's drop
// (closed forms), the bypass closes as the spool opens and the load check
// never lets the load flow back; through the C ABI its jacobian matches
// central differences.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"
#include "plugins/fake_host.hpp"

namespace mh::test {
namespace {

constexpr double kPump = 1e-4, kTank = 1e5, kLoad = 8e6, kCvd = 2e-8, kBypassDrop = 1e6;

TEST(OpenCentreValve, NeutralBypassesThePumpAndTheOpenValveFeedsTheLoad) {
  const ModelFile file = parse_model_text(example_model("open-centre-valve"), "oc.yaml");
  Simulation sim(file, build_plugins());
  sim.start();
  const int supply = sim.state_index("supply");
  const int spool = sim.state_index("valve.U");
  const int bypass = sim.output_index("valve.q_bypass");
  const int load_q = sim.state_index("load.q");
  ASSERT_GE(supply, 0);
  ASSERT_GE(spool, 0);
  ASSERT_GE(bypass, 0);
  ASSERT_GE(load_q, 0);
  double previous_bypass = 1.0, backflow = 0.0;
  bool monotone = true;
  while (sim.time() < 1.0 - 1e-9) {
    sim.step();
    if (std::abs(sim.time() - 0.1) < 1e-9) {
      // Neutral: the centre passes the pump's flow at its nominal drop.
      EXPECT_NEAR(sim.states()[supply], kTank + kBypassDrop, 1e-3 * kBypassDrop);
      EXPECT_NEAR(sim.outputs()[bypass], kPump, 1e-6 * kPump);
    }
    const double q_b = sim.outputs()[bypass];
    monotone = monotone && q_b <= previous_bypass + 1e-12;
    previous_bypass = q_b;
    backflow = std::max(backflow, sim.states()[load_q]);  // > 0: the load would feed P
  }
  EXPECT_TRUE(monotone) << "the centre passage closes as the spool opens";
  EXPECT_LE(backflow, 0.0) << "the load check let the load flow back";
  // Open (10 V, the centre shut at 6 V): all the pump's flow goes to the
  // load, across the edge's drop (Q / (C_vd U))^2.
  EXPECT_EQ(sim.outputs()[bypass], 0.0);
  const double drop = std::pow(kPump / (kCvd * 10.0), 2);
  EXPECT_NEAR(sim.states()[supply], kLoad + drop, 1e-3 * drop);
  EXPECT_NEAR(-sim.states()[load_q], kPump, 1e-4 * kPump);
  std::printf("[ measured ] open centre: neutral and open supply %.6g Pa (%.6g expected)\n",
              sim.states()[supply], kLoad + drop);
}

TEST(OpenCentreValve, AnalyticJacobianMatchesCentralDifferences) {
  FakeNetwork net;
  FakeHost host{net, "valve"};
  host.numbers = {{"flow_coefficient", kCvd},
                  {"nominal_bypass_flow", kPump},
                  {"closing_spool", 6.0},
                  {"time_constant", 0.02}};
  host.tables["reference"] = {2u, {0, 5}};
  host.port_nodes = {{"P", "p"}, {"T", "t"}, {"A", "a"}, {"B", "b"}};
  Instance valve("open-centre-valve", host);
  ASSERT_EQ(valve.setup(), MH_OK) << host.all_logs();
  const int32_t p = host.port("P").index, t = host.port("T").index;
  const int32_t a = host.port("A").index, b = host.port("B").index;
  const int32_t u = host.states.at(0).index;
  double worst = 0.0;
  for (const double spool : {0.7, 1.5, 5.9, 6.5, -3.0}) {  // not 0: |U| has its kink there
    for (const double supply : {9e6, 5e6}) {               // above and below the 8 MPa port
      Evaluation e(net);
      e.y[p] = supply;
      e.y[t] = kTank;
      e.y[a] = kLoad;
      e.y[b] = 7e6;
      e.y[u] = spool;
      worst = std::max(worst, jacobian_error(valve, e));
    }
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[ measured ] open-centre-valve jacobian max relative error %.3g\n", worst);
}

TEST(OpenCentreValve, AClosingPositionBeyondTheSpoolsLimitIsRefused) {
  FakeNetwork net;
  FakeHost host{net, "valve"};
  host.numbers = {{"flow_coefficient", kCvd},
                  {"nominal_bypass_flow", kPump},
                  {"closing_spool", 12.0},
                  {"time_constant", 0.02}};
  host.tables["reference"] = {2u, {0, 5}};
  host.port_nodes = {{"P", "p"}, {"T", "t"}, {"A", "a"}, {"B", "b"}};
  Instance valve("open-centre-valve", host);
  EXPECT_EQ(valve.setup(), MH_ERROR);
  EXPECT_EQ(host.option_errors, std::vector<std::string>{"closing_spool"});
}

}  // namespace
}  // namespace mh::test
