// The inverse_dynamics service (sdk inverse_dynamics.h,
// core/src/plugins/host_services.cpp): a formulation that takes its rows from
// it follows open-loop's motion, and the calls it must not make are refused
// with a logged reason, not carried out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

TEST(InverseDynamicsService, ARunOnItFollowsOpenLoopAndBadCallsAreRefusedSayingWhy) {
  ModelFile file = load_model_file(source_path("models/double-pendulum.yaml"));
  file.solver.t_end = 0.5;
  std::vector<std::string> errors;
  const LogSink sink = [&errors](mh_log_level level, const std::string&, const std::string& msg) {
    if (level == MH_LOG_ERROR) errors.push_back(msg);
  };
  const std::string fixture = std::string(mh::test::paths::inverse_dynamics_plugin_dir) +
                              "/inverse_dynamics_formulation.so";
  Simulation on_service(file, build_plugins_with(fixture), "inverse-dynamics-formulation", sink);
  Simulation open_loop(file, build_plugins(), "open-loop");
  on_service.start();
  open_loop.start();
  double gap = 0.0;
  while (open_loop.time() < 0.5 - 1e-9) {
    on_service.step();
    open_loop.step();
    gap = std::max(gap, (on_service.z() - open_loop.z()).lpNorm<Eigen::Infinity>());
  }
  ::testing::Test::RecordProperty("gap", scientific(gap));
  EXPECT_GT(open_loop.z().norm(), 0.5);  // it swung
  // The same equations, solved to the same 1e-7 rad tolerance (the fixture's
  // tangent is the host's differences): measured 1.3e-11 rad.
  EXPECT_LT(gap, 1e-9);
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0],
            "inverse_dynamics: flags: expected MH_EVAL_SUBSYSTEMS at most (the dynamics are "
            "implied; constraints are evaluate_mechanics's)");
  EXPECT_EQ(errors[1], "inverse_dynamics: for a formulation, with z, zd, zdd and r");
}

}  // namespace
}  // namespace mh::test
