// The C++ layer over the embedding API (monohydra/simulation.hpp): a PI loop
// written in the program drives the four-bar's valve and holds the boom
// where models/fourbar-position-control.yaml's in-model loop holds it; a
// snapshot through bytes continues to the bit; a failing call throws
// monohydra::Error with the library's status and message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/simulation.hpp"

namespace {

std::string model(const std::string& name) {
  return std::string(mh::test::paths::source_dir) + "/models/" + name;
}

// The same PI (kp 600 V/m, ki 500 V/(m s), +-10 V with back-calculation) in
// the program, sampled at every step, moves the stroke out by 20 mm: it ends
// within 1e-4 m of the in-model loop, which computes it inside the Newton
// step (so the two differ by the one-step delay of the sampled loop alone).
TEST(SimulationCpp, AProgramsPiLoopHoldsTheBoomWhereTheInModelLoopDoes) {
  monohydra::Simulation open =
      monohydra::Simulation::open_file(model("fourbar.yaml"), {{"t_end", "4"}});
  monohydra::Simulation loop =
      monohydra::Simulation::open_file(model("fourbar-position-control.yaml"), {{"t_end", "4"}});
  open.start();
  loop.start();
  const uint32_t command = open.find("valve_command"), s = open.find("s");
  const uint32_t stroke = loop.find("stroke");
  const double s0 = open.get(s), kp = 600.0, ki = 500.0, tt = kp / ki;
  double integral = 0.0;
  while (open.time() < 4.0 - 1e-9) {
    const double setpoint = open.time() >= 1.0 - 1e-9 ? 0.02 : 0.0;
    const double e = setpoint - (open.get(s) - s0);
    const double v = kp * e + integral;
    const double u = std::clamp(v, -10.0, 10.0);
    integral += 1e-3 * (ki * e + (u - v) / tt);
    open.set(command, u);
    open.step();
    loop.step();
  }
  EXPECT_NEAR(open.get(s) - s0, 0.02, 2e-3);  // near the setpoint, still settling
  EXPECT_NEAR(open.get(s) - s0, loop.get(stroke), 1e-4);
}

TEST(SimulationCpp, SnapshotBytesContinueToTheBit) {
  monohydra::Simulation sim =
      monohydra::Simulation::open_file(model("fourbar.yaml"), {{"formulation", "penalty"}});
  sim.advance(1.5);
  monohydra::Snapshot at = sim.snapshot();
  const std::vector<unsigned char> bytes = sim.bytes(at);
  sim.advance(3.0);
  const std::vector<double> first = sim.row();
  monohydra::Simulation other =
      monohydra::Simulation::open_file(model("fourbar.yaml"), {{"formulation", "penalty"}});
  const monohydra::Snapshot read = other.snapshot_from(bytes);
  other.restore(read);
  EXPECT_DOUBLE_EQ(other.time(), 1.5);
  other.advance(3.0);
  EXPECT_EQ(other.row(), first);
  EXPECT_EQ(other.row_text(false), sim.row_text(false));
  EXPECT_EQ(other.steps(), 3000);
}

TEST(SimulationCpp, FailingCallsThrowWithTheStatusAndTheLibrarysMessage) {
  try {
    (void)monohydra::Simulation::open_file(model("no-such-model.yaml"));
    FAIL() << "a missing model opened";
  } catch (const monohydra::Error& err) {
    EXPECT_EQ(err.status(), MHS_FATAL);
    EXPECT_NE(std::string(err.what()).find("no-such-model.yaml"), std::string::npos) << err.what();
  }
  monohydra::Simulation sim = monohydra::Simulation::open_file(model("fourbar.yaml"));
  try {
    (void)sim.find("boom");
    FAIL() << "an unknown name was found";
  } catch (const monohydra::Error& err) {
    EXPECT_EQ(err.status(), MHS_ERROR);
    EXPECT_NE(std::string(err.what()).find("'boom'"), std::string::npos) << err.what();
  }
  sim.start();  // set before it, an input is the initial value the equilibrium must hold
  const uint32_t command = sim.find("valve_command");
  EXPECT_THROW(sim.set(command, std::nan("")), monohydra::Error);
  EXPECT_THROW(sim.set(command, 11.0), monohydra::Error);  // outside [-10, 10]: refused
  sim.set(command, 5.0);
  sim.step();
  EXPECT_DOUBLE_EQ(sim.get(command), 5.0);
  const std::vector<monohydra::Variable> vars = sim.variables();
  EXPECT_TRUE(std::any_of(vars.begin(), vars.end(), [](const monohydra::Variable& v) {
    return v.name == "valve_command" && v.kind == MHS_INPUT && v.unit == "V" && v.min == -10.0;
  }));
}

TEST(SimulationCpp, ABatchSaysHowManyRunsStoppedAndWhyWithoutThrowing) {
  monohydra::Batch batch = monohydra::Batch::open_file(model("fourbar.yaml"), 3, 2);
  EXPECT_EQ(batch.size(), 3u);
  EXPECT_EQ(batch.threads(), 2u);
  EXPECT_EQ(batch.dt(), 1e-3);
  batch.set_parameter(2, "subsystems/valve/flow_coefficient", 2e-5);  // fails as the valve opens
  EXPECT_EQ(batch.advance(0.5), 0u);
  EXPECT_EQ(batch.advance(1.2), 1u);
  EXPECT_NE(batch.warning().find("run 2: t = 1.001 s"), std::string::npos) << batch.warning();
  const monohydra::Batch::RunStatus stopped = batch.status(2);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(stopped.steps, 1000);
  EXPECT_FALSE(batch.status(0).stopped);
  const std::vector<double> z1 = batch.get("z1");
  ASSERT_EQ(z1.size(), 3u);
  EXPECT_EQ(z1[0], z1[1]);  // the same parameters, the same run
  EXPECT_NE(z1[0], z1[2]);
  try {
    batch.advance(0.1);
    ADD_FAILURE() << "an advance into the past did not throw";
  } catch (const monohydra::Error& e) {
    EXPECT_EQ(e.status(), MHS_ERROR);
    EXPECT_NE(std::string(e.what()).find("before run 0's time"), std::string::npos) << e.what();
  }
}

}  // namespace
