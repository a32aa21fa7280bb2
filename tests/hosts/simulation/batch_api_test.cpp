// The embedding API's batches (simulation.h 1.5, mhs_batch_*) through the C
// header alone: each run of a batch stepped on two threads is, to the bit,
// the same run stepped alone; a run that fails stops alone with its reason
// while the others go on; a batch's snapshot puts every run back; inputs
// differ run by run; every bad call returns a status and a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/simulation.h"
#include "same_bits.hpp"
#include "text_file.hpp"

namespace {

using mh::test::read_text;

struct Free {
  void operator()(mhs_simulation* s) const { mhs_free(s); }
  void operator()(mhs_batch* b) const { mhs_batch_free(b); }
  void operator()(mhs_batch_snapshot* s) const { mhs_batch_snapshot_free(s); }
};
using Sim = std::unique_ptr<mhs_simulation, Free>;
using Batch = std::unique_ptr<mhs_batch, Free>;
using BatchSnapshot = std::unique_ptr<mhs_batch_snapshot, Free>;

std::string model(const std::string& name) {
  return std::string(mh::test::paths::source_dir) + "/models/" + name;
}

bool ok(mhs_status st) {
  return st == MHS_OK || st == MHS_WARNING;
}

// One run's parameters: the valve's flow coefficient, the load's mass, the
// cylinder fluid's bulk modulus.
struct Parameters {
  double flow = 0.0, mass = 0.0, bulk = 0.0;
};
const char* const kPaths[] = {"subsystems/valve/flow_coefficient", "bodies/body3/mass",
                              "subsystems/cylinder/fluid_bulk_modulus"};

// Within +-20 % of the four-bar's (2.138e-8, 50 kg, 1.5 GPa), seeded.
std::vector<Parameters> randomised(size_t n) {
  std::mt19937 rng(20261207);
  std::uniform_real_distribution<double> f(0.8, 1.2);
  std::vector<Parameters> out(n);
  for (Parameters& p : out) p = {2.138e-8 * f(rng), 50.0 * f(rng), 1.5e9 * f(rng)};
  return out;
}

Batch open_batch(const std::string& name, uint32_t runs, uint32_t threads,
                 std::vector<mhs_setting> settings = {}) {
  mhs_batch* b = nullptr;
  const mhs_status st =
      mhs_batch_open_file(model(name).c_str(), settings.data(), settings.size(), runs, threads, &b);
  EXPECT_EQ(st, MHS_OK) << mhs_batch_message(b);
  return Batch(b);
}

void set(mhs_batch* b, uint32_t run, const Parameters& p) {
  const double values[] = {p.flow, p.mass, p.bulk};
  for (size_t j = 0; j < 3; ++j)
    EXPECT_EQ(mhs_batch_set_parameter(b, run, kPaths[j], values[j]), MHS_OK)
        << mhs_batch_message(b);
}

// Every value of a run alone with `p`, at `t`.
std::vector<double> alone(const std::string& name, const Parameters& p, double t,
                          std::vector<mhs_setting> settings = {}) {
  mhs_simulation* raw = nullptr;
  EXPECT_EQ(mhs_open_file(model(name).c_str(), settings.data(), settings.size(), &raw), MHS_OK)
      << mhs_message(raw);
  const Sim sim(raw);
  const double values[] = {p.flow, p.mass, p.bulk};
  for (size_t j = 0; j < 3; ++j)
    EXPECT_EQ(mhs_set_parameter(sim.get(), kPaths[j], values[j]), MHS_OK) << mhs_message(raw);
  EXPECT_TRUE(ok(mhs_advance(sim.get(), t))) << mhs_message(raw);
  uint32_t count = 0;
  EXPECT_EQ(mhs_variable_count(sim.get(), &count), MHS_OK);
  std::vector<double> out(count);
  for (uint32_t i = 0; i < count; ++i) EXPECT_EQ(mhs_get(sim.get(), &i, 1, &out[i]), MHS_OK);
  return out;
}

// Value `index` of every run.
std::vector<double> column(mhs_batch* b, uint32_t index, size_t runs) {
  std::vector<double> out(runs);
  EXPECT_EQ(mhs_batch_get(b, index, out.data(), out.size()), MHS_OK) << mhs_batch_message(b);
  return out;
}

using mh::test::same_bits;

TEST(EmbeddingBatch, EachRunOfABatchOnTwoThreadsIsThatRunSteppedAloneToTheBit) {
  const size_t n = 6;
  const double t = 1.5;  // through the valve's opening at 1 s
  const std::vector<Parameters> params = randomised(n);
  const Batch b = open_batch("fourbar.yaml", n, 2);
  uint32_t runs = 0, threads = 0;
  ASSERT_EQ(mhs_batch_size(b.get(), &runs, &threads), MHS_OK);
  EXPECT_EQ(runs, n);
  EXPECT_EQ(threads, 2u);
  for (uint32_t k = 0; k < n; ++k) set(b.get(), k, params[k]);
  ASSERT_EQ(mhs_batch_advance(b.get(), t), MHS_OK) << mhs_batch_message(b.get());
  uint32_t count = 0;
  ASSERT_EQ(mhs_batch_variable_count(b.get(), &count), MHS_OK);
  std::vector<std::vector<double>> by_variable;
  for (uint32_t i = 0; i < count; ++i) by_variable.push_back(column(b.get(), i, n));
  // The parameters move the run: the load's angle differs run to run.
  uint32_t z1 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "z1", &z1), MHS_OK);
  EXPECT_GT(std::abs(by_variable[z1][0] - by_variable[z1][1]), 1e-4);
  for (size_t k = 0; k < n; ++k) {
    const std::vector<double> single = alone("fourbar.yaml", params[k], t);
    ASSERT_EQ(single.size(), count);
    for (uint32_t i = 0; i < count; ++i)
      EXPECT_TRUE(same_bits(by_variable[i][k], single[i]))
          << "run " << k << ", value " << i << ": " << by_variable[i][k] << " in the batch, "
          << single[i] << " alone";
  }
}

TEST(EmbeddingBatch, ARunWhoseStepFailsStopsAloneWithItsReasonWhileTheOthersGoOn) {
  const Batch b = open_batch("fourbar.yaml", 3, 2);
  // A valve a thousand times too wide: Newton fails as the valve opens at 1 s.
  ASSERT_EQ(mhs_batch_set_parameter(b.get(), 1, kPaths[0], 2e-5), MHS_OK);
  const mhs_status st = mhs_batch_advance(b.get(), 1.2);
  EXPECT_EQ(st, MHS_DISCARD);
  const std::string message = mhs_batch_message(b.get());
  EXPECT_NE(message.find("1 of 3 runs are stopped"), std::string::npos) << message;
  EXPECT_NE(message.find("run 1: "), std::string::npos) << message;
  EXPECT_NE(message.find("t = 1.001 s"), std::string::npos) << message;
  for (uint32_t k = 0; k < 3; ++k) {
    mhs_status run = MHS_FATAL;
    double t = 0.0;
    int64_t steps = 0;
    const char* why = nullptr;
    ASSERT_EQ(mhs_batch_run_status(b.get(), k, &run, &t, &steps, &why), MHS_OK);
    if (k == 1) {
      EXPECT_EQ(run, MHS_ERROR);
      EXPECT_NEAR(t, 1.0, 1e-9);  // its last accepted state
      EXPECT_EQ(steps, 1000);
      EXPECT_NE(std::string(why).find("Newton did not converge"), std::string::npos) << why;
    } else {
      EXPECT_EQ(run, MHS_OK);
      EXPECT_NEAR(t, 1.2, 1e-9);
      EXPECT_STREQ(why, "");
    }
  }
  // The others go on; the stopped run takes no step and is named again.
  EXPECT_EQ(mhs_batch_step(b.get(), 10), MHS_DISCARD);
  for (uint32_t k = 0; k < 3; ++k) {
    mhs_status run = MHS_FATAL;
    double t = 0.0;
    ASSERT_EQ(mhs_batch_run_status(b.get(), k, &run, &t, nullptr, nullptr), MHS_OK);
    EXPECT_NEAR(t, k == 1 ? 1.0 : 1.21, 1e-9) << "run " << k;
  }
}

TEST(EmbeddingBatch, ARestoredSnapshotRepeatsEveryRunToTheBitAndForgetsAStop) {
  const Batch b = open_batch("fourbar.yaml", 3, 2);
  ASSERT_EQ(mhs_batch_set_parameter(b.get(), 2, kPaths[1], 80.0), MHS_OK);
  ASSERT_EQ(mhs_batch_advance(b.get(), 0.9), MHS_OK);
  mhs_batch_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_batch_snapshot_new(b.get(), &raw), MHS_OK);
  const BatchSnapshot snap(raw);
  ASSERT_EQ(mhs_batch_save(b.get(), snap.get()), MHS_OK) << mhs_batch_message(b.get());
  uint32_t p2 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "p2", &p2), MHS_OK);
  ASSERT_EQ(mhs_batch_advance(b.get(), 1.3), MHS_OK);
  const std::vector<double> first = column(b.get(), p2, 3);
  EXPECT_NE(first[0], first[2]);  // the heavier load
  ASSERT_EQ(mhs_batch_restore(b.get(), snap.get()), MHS_OK);
  double t = 0.0;
  mhs_status run = MHS_FATAL;
  ASSERT_EQ(mhs_batch_run_status(b.get(), 0, &run, &t, nullptr, nullptr), MHS_OK);
  EXPECT_NEAR(t, 0.9, 1e-9);
  ASSERT_EQ(mhs_batch_advance(b.get(), 1.3), MHS_OK);
  const std::vector<double> again = column(b.get(), p2, 3);
  for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(first[k], again[k])) << "run " << k;
  // A run stopped after the snapshot goes on from it once restored.
  ASSERT_EQ(mhs_batch_set_parameter(b.get(), 0, kPaths[0], 2e-5), MHS_OK);
  ASSERT_EQ(mhs_batch_restore(b.get(), snap.get()), MHS_OK);
  EXPECT_EQ(mhs_batch_advance(b.get(), 1.3), MHS_DISCARD);
  ASSERT_EQ(mhs_batch_set_parameter(b.get(), 0, kPaths[0], 2.138e-8), MHS_OK);
  ASSERT_EQ(mhs_batch_restore(b.get(), snap.get()), MHS_OK);
  EXPECT_EQ(mhs_batch_advance(b.get(), 1.3), MHS_OK) << mhs_batch_message(b.get());
  EXPECT_TRUE(same_bits(column(b.get(), p2, 3)[0], first[0]));
}

TEST(EmbeddingBatch, EachRunTakesItsOwnInputAndAClampedOneIsNamed) {
  const Batch b = open_batch("fourbar.yaml", 2, 2);
  uint32_t u = 0, z1 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "valve_command", &u), MHS_OK);
  ASSERT_EQ(mhs_batch_find(b.get(), "z1", &z1), MHS_OK);
  ASSERT_EQ(mhs_batch_advance(b.get(), 0.2), MHS_OK);
  const double commands[] = {5.0, -5.0};
  ASSERT_EQ(mhs_batch_set(b.get(), u, commands, 2), MHS_OK) << mhs_batch_message(b.get());
  EXPECT_EQ(column(b.get(), u, 2), std::vector<double>({5.0, -5.0}));
  const std::vector<double> before = column(b.get(), z1, 2);
  ASSERT_EQ(mhs_batch_advance(b.get(), 0.5), MHS_OK);
  const std::vector<double> after = column(b.get(), z1, 2);
  // Opposite commands move the load opposite ways.
  EXPECT_LT((after[0] - before[0]) * (after[1] - before[1]), 0.0);
  // Refused for one run, set for none.
  const double wide[] = {0.0, 1e3};
  EXPECT_EQ(mhs_batch_set(b.get(), u, wide, 2), MHS_ERROR);
  const std::string refused = mhs_batch_message(b.get());
  EXPECT_NE(refused.find("mhs_batch_set: run 1: "), std::string::npos) << refused;
  EXPECT_EQ(column(b.get(), u, 2), std::vector<double>({5.0, -5.0}));
  // Clamped where the model says so, and each clamped run named.
  std::string text = read_text(model("fourbar.yaml"));
  const std::string range = "    range: [-10, 10]\n";
  ASSERT_NE(text.find(range), std::string::npos);
  text.insert(text.find(range) + range.size(), "    out_of_range: clamp\n");
  mhs_batch* raw = nullptr;
  ASSERT_EQ(mhs_batch_open_text(text.c_str(), "clamping four-bar", model("").c_str(), nullptr, 0, 2,
                                2, &raw),
            MHS_OK)
      << mhs_batch_message(raw);
  const Batch c(raw);
  EXPECT_EQ(mhs_batch_set(c.get(), u, wide, 2), MHS_WARNING);
  const std::string clamped = mhs_batch_message(c.get());
  EXPECT_NE(clamped.find("run 1: input 'valve_command' clamped from 1000 to 10"), std::string::npos)
      << clamped;
  EXPECT_EQ(clamped.find("run 0"), std::string::npos) << clamped;
  EXPECT_EQ(column(c.get(), u, 2), std::vector<double>({0.0, 10.0}));
}

TEST(EmbeddingBatch, ASecondThreadsCallOnABusyBatchIsRefusedAndChangesNothing) {
  const Batch b = open_batch("fourbar.yaml", 2, 2);
  ASSERT_TRUE(ok(mhs_batch_start(b.get())));
  uint32_t z1 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "z1", &z1), MHS_OK);
  // One long call in another thread (days of model time, until cancelled);
  // tried again when this thread's call refused it. No assertion may end
  // the test before the thread is joined.
  std::thread stepping([&] {
    while (mhs_batch_advance(b.get(), 1e6) == MHS_ERROR) {
    }
  });
  int refused = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (refused == 0 && std::chrono::steady_clock::now() < until) {
    double values[2] = {-1.0, -1.0};
    const mhs_status st = mhs_batch_get(b.get(), z1, values, 2);
    if (st == MHS_OK) continue;
    ++refused;
    EXPECT_EQ(st, MHS_ERROR);
    EXPECT_EQ(values[0], -1.0);  // nothing written
    EXPECT_EQ(values[1], -1.0);
    EXPECT_NE(std::string(mhs_batch_message(b.get())).find("another thread is in a call"),
              std::string::npos)
        << mhs_batch_message(b.get());
  }
  mhs_batch_cancel(b.get());
  stepping.join();
  EXPECT_EQ(refused, 1);
  // Alone again: calls go through, and the message is the batch's own (the
  // other thread's cancelled advance).
  double values[2] = {};
  EXPECT_EQ(mhs_batch_get(b.get(), z1, values, 2), MHS_OK);
  EXPECT_NE(std::string(mhs_batch_message(b.get())).find("cancelled"), std::string::npos)
      << mhs_batch_message(b.get());
}

TEST(EmbeddingBatch, CancelEndsALongAdvanceBetweenTwoStepsAndTheRunsGoOn) {
  const Batch b = open_batch("fourbar.yaml", 3, 2);
  ASSERT_TRUE(ok(mhs_batch_start(b.get())));
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    mhs_batch_cancel(b.get());
  });
  const mhs_status st = mhs_batch_advance(b.get(), 1e6);  // days of model time
  canceller.join();
  EXPECT_EQ(st, MHS_DISCARD);
  const std::string message = mhs_batch_message(b.get());
  EXPECT_NE(message.find("mhs_batch_advance: cancelled (mhs_batch_cancel)"), std::string::npos)
      << message;
  // Each run at an accepted state, none stopped, none near the end.
  double latest = 0.0;
  for (uint32_t k = 0; k < 3; ++k) {
    mhs_status run_status = MHS_ERROR;
    double t = -1.0;
    int64_t steps = -1;
    ASSERT_EQ(mhs_batch_run_status(b.get(), k, &run_status, &t, &steps, nullptr), MHS_OK);
    EXPECT_EQ(run_status, MHS_OK) << "run " << k;
    EXPECT_GE(t, 0.0) << "run " << k;
    EXPECT_LT(t, 1e3) << "run " << k;
    EXPECT_NEAR(t, static_cast<double>(steps) * 1e-3, 1e-9) << "run " << k;  // at a step
    latest = std::max(latest, t);
  }
  // The message stays through calls that succeed, until the next that does not.
  uint32_t z1 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "z1", &z1), MHS_OK);
  EXPECT_EQ(std::string(mhs_batch_message(b.get())), message);
  // They go on from there.
  EXPECT_EQ(mhs_batch_advance(b.get(), latest + 0.01), MHS_OK) << mhs_batch_message(b.get());
  // A cancel with no call in flight ends the next one at its start.
  mhs_batch_cancel(b.get());
  EXPECT_EQ(mhs_batch_step(b.get(), 5), MHS_DISCARD);
  mhs_status run_status = MHS_ERROR;
  int64_t before = -1;
  ASSERT_EQ(mhs_batch_run_status(b.get(), 0, &run_status, nullptr, &before, nullptr), MHS_OK);
  EXPECT_EQ(mhs_batch_step(b.get(), 5), MHS_OK) << mhs_batch_message(b.get());
  int64_t after = -1;
  ASSERT_EQ(mhs_batch_run_status(b.get(), 0, &run_status, nullptr, &after, nullptr), MHS_OK);
  EXPECT_EQ(after, before + 5);
  mhs_batch_cancel(nullptr);  // ignored
}

TEST(EmbeddingBatch, BadCallsReturnAStatusAndAMessageNamingWhatIsWrong) {
  mhs_batch* raw = nullptr;
  EXPECT_EQ(mhs_batch_open_file(model("fourbar.yaml").c_str(), nullptr, 0, 0, 1, &raw), MHS_FATAL);
  EXPECT_NE(std::string(mhs_batch_message(raw)).find("at least one run"), std::string::npos)
      << mhs_batch_message(raw);
  mhs_batch_free(raw);
  EXPECT_EQ(mhs_batch_open_file(model("nonexistent.yaml").c_str(), nullptr, 0, 2, 1, &raw),
            MHS_FATAL);
  EXPECT_NE(std::string(mhs_batch_message(raw)).find("nonexistent.yaml"), std::string::npos)
      << mhs_batch_message(raw);
  EXPECT_EQ(mhs_batch_advance(raw, 1.0), MHS_FATAL);
  mhs_batch_free(raw);
  EXPECT_EQ(mhs_batch_advance(nullptr, 1.0), MHS_ERROR);
  EXPECT_STREQ(mhs_batch_message(nullptr), "the batch handle is NULL");

  const Batch b = open_batch("fourbar.yaml", 2, 1);
  const auto says = [&](mhs_status st, const std::string& words) {
    EXPECT_EQ(st, MHS_ERROR);
    EXPECT_NE(std::string(mhs_batch_message(b.get())).find(words), std::string::npos)
        << mhs_batch_message(b.get());
  };
  says(mhs_batch_set_parameter(b.get(), 2, kPaths[1], 60.0), "run 2: the batch has 2 runs");
  says(mhs_batch_set_parameter(b.get(), 0, "bodies/body9/mass", 60.0), "body9");
  says(mhs_batch_set_parameter(b.get(), 0, kPaths[1], -1.0), "mass");
  says(mhs_batch_set_parameter(b.get(), 0, kPaths[1], NAN), "expected a finite value");
  says(mhs_batch_advance(b.get(), INFINITY), "not a finite time");
  double two[2] = {};
  uint32_t z1 = 0;
  ASSERT_EQ(mhs_batch_find(b.get(), "z1", &z1), MHS_OK);
  says(mhs_batch_get(b.get(), z1, two, 3), "3 values for 2 runs");
  says(mhs_batch_get(b.get(), 100000, two, 2), "index 100000 is not below");
  says(mhs_batch_set(b.get(), z1, two, 2), "'z1' is not an input");
  says(mhs_batch_find(b.get(), "nothing", &z1), "no value 'nothing'");
  mhs_batch_snapshot* snap = nullptr;
  ASSERT_EQ(mhs_batch_snapshot_new(b.get(), &snap), MHS_OK);
  says(mhs_batch_restore(b.get(), snap), "holds no state yet");
  says(mhs_batch_save(b.get(), snap), "run 0 has not started");
  ASSERT_EQ(mhs_batch_advance(b.get(), 0.1), MHS_OK);
  says(mhs_batch_advance(b.get(), 0.05), "before run 0's time");
  const Batch other = open_batch("fourbar.yaml", 2, 1);
  ASSERT_EQ(mhs_batch_advance(other.get(), 0.1), MHS_OK);
  EXPECT_EQ(mhs_batch_save(other.get(), snap), MHS_ERROR);
  EXPECT_NE(std::string(mhs_batch_message(other.get())).find("another batch"), std::string::npos);
  mhs_batch_snapshot_free(snap);
  // Bytes that are not a batch's snapshot, or cut short, are refused.
  ASSERT_EQ(mhs_batch_snapshot_new(b.get(), &snap), MHS_OK);
  ASSERT_EQ(mhs_batch_save(b.get(), snap), MHS_OK);
  const void* bytes = nullptr;
  size_t size = 0;
  ASSERT_EQ(mhs_batch_snapshot_bytes(b.get(), snap, &bytes, &size), MHS_OK);
  std::vector<unsigned char> copy(static_cast<const unsigned char*>(bytes),
                                  static_cast<const unsigned char*>(bytes) + size);
  const unsigned char junk[] = "not a snapshot at all";
  says(mhs_batch_snapshot_read(b.get(), snap, junk, sizeof junk), "not a batch's snapshot");
  says(mhs_batch_snapshot_read(b.get(), snap, copy.data(), copy.size() / 2), "cut short");
  copy[copy.size() - 3] ^= 0xff;  // in run 1's checksum
  says(mhs_batch_snapshot_read(b.get(), snap, copy.data(), copy.size()), "run 1: ");
  copy[copy.size() - 3] ^= 0xff;
  EXPECT_EQ(mhs_batch_snapshot_read(b.get(), snap, copy.data(), copy.size()), MHS_OK);
  EXPECT_EQ(mhs_batch_restore(b.get(), snap), MHS_OK) << mhs_batch_message(b.get());
  mhs_batch_snapshot_free(snap);
}

}  // namespace
