// The embedding API (hosts/simulation, monohydra/simulation.h) through its C
// header alone, as an embedding program uses it: its rows are the command
// line's to the byte, a restored snapshot repeats the run to the bit (in
// this process and, as bytes, in another), four threads give the serial
// results, and every bad call returns a status and a message naming it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/simulation.h"
#include "text_file.hpp"

namespace {

using mh::test::read_text;

struct Free {
  void operator()(mhs_simulation* s) const { mhs_free(s); }
  void operator()(mhs_snapshot* s) const { mhs_snapshot_free(s); }
};
using Sim = std::unique_ptr<mhs_simulation, Free>;
using Snapshot = std::unique_ptr<mhs_snapshot, Free>;

std::string model(const std::string& name) {
  return std::string(mh::test::paths::source_dir) + "/models/" + name;
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir =
      std::filesystem::path(mh::test::paths::binary_dir) / "test-scratch" / "simulation" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Opens `name` with the settings; fails the test unless it opened.
Sim open(const std::string& name, std::vector<mhs_setting> settings = {}) {
  mhs_simulation* sim = nullptr;
  const mhs_status st = mhs_open_file(model(name).c_str(), settings.data(), settings.size(), &sim);
  EXPECT_LE(st, MHS_WARNING) << mhs_message(sim);
  return Sim(sim);
}

bool ok(mhs_status st) {
  return st == MHS_OK || st == MHS_WARNING;
}

std::string row_text(mhs_simulation* sim, bool header = false) {
  std::vector<char> text(1 << 16);
  size_t length = 0;
  EXPECT_EQ(mhs_row_text(sim, header ? 1 : 0, text.data(), text.size(), &length), MHS_OK)
      << mhs_message(sim);
  return std::string(text.data(), length);
}

// The rows of every step up to `t_end`, as text.
std::string rows_until(mhs_simulation* sim, double t_end) {
  std::string rows;
  double t = 0.0, dt = 0.0;
  EXPECT_EQ(mhs_time(sim, &t, nullptr, &dt, nullptr), MHS_OK);
  while (t < t_end - 0.5 * dt) {
    const mhs_status st = mhs_step(sim);
    if (!ok(st)) {
      ADD_FAILURE() << "mhs_step at t = " << t << ": " << mhs_message(sim);
      break;
    }
    rows += row_text(sim);
    EXPECT_EQ(mhs_time(sim, &t, nullptr, nullptr, nullptr), MHS_OK);
  }
  return rows;
}

// `monohydra run MODEL ARGS --out` 's CSV.
std::string cli_csv(const std::string& name, const std::string& args, const std::string& tag) {
  const auto out = scratch("cli-" + tag) / "run.csv";
  const std::string command = std::string(mh::test::paths::executable) + " run " + model(name) +
                              " " + args + " --out " + out.string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return read_text(out);
}

// Every row the run writes, as `monohydra run` writes its CSV.
std::string api_csv(mhs_simulation* sim) {
  std::string csv = row_text(sim, true);
  EXPECT_TRUE(ok(mhs_start(sim))) << mhs_message(sim);
  double t = 0.0, dt = 0.0, t_end = 0.0;
  EXPECT_EQ(mhs_time(sim, &t, nullptr, &dt, &t_end), MHS_OK);
  for (;;) {
    int32_t due = 0;
    EXPECT_EQ(mhs_row_due(sim, &due), MHS_OK);
    if (due != 0) csv += row_text(sim);
    if (t >= t_end - 0.5 * dt) break;
    if (!ok(mhs_step(sim))) {
      ADD_FAILURE() << mhs_message(sim);
      break;
    }
    EXPECT_EQ(mhs_time(sim, &t, nullptr, nullptr, nullptr), MHS_OK);
  }
  return csv;
}

TEST(EmbeddingRun, RowsAreTheCommandLinesCsvByteForByte) {
  Sim sim = open("fourbar.yaml");
  EXPECT_EQ(api_csv(sim.get()), cli_csv("fourbar.yaml", "", "fourbar"));
}

TEST(EmbeddingRun, SettingsChooseAsTheCommandLinesFlagsDo) {
  Sim sim =
      open("quickreturn.yaml", {{"formulation", "penalty"}, {"dt", "0.002"}, {"t_end", "1.5"}});
  EXPECT_EQ(api_csv(sim.get()),
            cli_csv("quickreturn.yaml", "--formulation penalty --dt 0.002 --t-end 1.5", "qr"));
}

TEST(EmbeddingRun, AValueSetByItsPathIsTheModelFileWithThatValue) {
  // The pump at 9 MPa instead of the paper's 7.6, by path here and in an
  // edited copy of the file for the command line.
  std::string text = read_text(model("fourbar.yaml"));
  const std::string from = "pressure: 7.6e6";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "pressure: 9e6");
  const auto edited = scratch("edited") / "fourbar-9MPa.yaml";
  std::ofstream(edited) << text;
  const auto out = edited.parent_path() / "run.csv";
  const std::string command = std::string(mh::test::paths::executable) + " run " + edited.string() +
                              " --t-end 2 --out " + out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  Sim sim = open("fourbar.yaml", {{"subsystems/pump/pressure", "9e6"}, {"t_end", "2"}});
  const std::string csv = api_csv(sim.get());
  EXPECT_EQ(csv, read_text(out));
  // And it is not the paper's pump.
  Sim paper = open("fourbar.yaml", {{"t_end", "2"}});
  EXPECT_NE(csv, api_csv(paper.get()));
  // From text, with the folder its relative paths start from.
  mhs_simulation* raw = nullptr;
  const mhs_setting two_s = {"t_end", "2"};
  ASSERT_LE(mhs_open_text(text.c_str(), "fourbar-9MPa.yaml", edited.parent_path().c_str(), &two_s,
                          1, &raw),
            MHS_WARNING)
      << mhs_message(raw);
  Sim by_text(raw);
  EXPECT_EQ(api_csv(by_text.get()), csv);
}

TEST(EmbeddingRun, ValuesAreNamedWithTheirUnitsAndReadAsTheRowHasThem) {
  Sim sim = open("fourbar.yaml");
  uint32_t count = 0;
  ASSERT_EQ(mhs_variable_count(sim.get(), &count), MHS_OK);
  ASSERT_GT(count, 6u);
  mhs_variable_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(mhs_variable(sim.get(), 0, &info), MHS_OK);
  EXPECT_STREQ(info.name, "z1");
  EXPECT_STREQ(info.unit, "rad");
  EXPECT_EQ(info.kind, MHS_COORDINATE);
  uint32_t p1 = 0, z1 = 0, rate = 0;
  ASSERT_EQ(mhs_find(sim.get(), "p1", &p1), MHS_OK) << mhs_message(sim.get());
  ASSERT_EQ(mhs_variable(sim.get(), p1, &info), MHS_OK);
  EXPECT_STREQ(info.unit, "Pa");
  EXPECT_EQ(info.kind, MHS_STATE);
  ASSERT_EQ(mhs_find(sim.get(), "z1", &z1), MHS_OK);
  ASSERT_EQ(mhs_find(sim.get(), "z1_dot", &rate), MHS_OK);
  ASSERT_EQ(mhs_variable(sim.get(), rate, &info), MHS_OK);
  EXPECT_STREQ(info.unit, "rad/s");
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 1.0))) << mhs_message(sim.get());
  double t = 0.0;
  int64_t steps = 0;
  ASSERT_EQ(mhs_time(sim.get(), &t, &steps, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(steps, 1000);
  // The values against the row's columns of the same names.
  uint32_t columns = 0;
  ASSERT_EQ(mhs_row_size(sim.get(), &columns), MHS_OK);
  std::vector<double> row(columns);
  ASSERT_EQ(mhs_row(sim.get(), row.data(), row.size()), MHS_OK);
  const uint32_t wanted[] = {z1, p1};
  double got[2] = {};
  ASSERT_EQ(mhs_get(sim.get(), wanted, 2, got), MHS_OK);
  const char* name = nullptr;
  for (uint32_t c = 0; c < columns; ++c) {
    ASSERT_EQ(mhs_row_name(sim.get(), c, &name), MHS_OK);
    const std::string column = name;
    if (column == "t") {
      EXPECT_EQ(row[c], t);
    } else if (column == "z1") {
      EXPECT_EQ(row[c], got[0]);
    } else if (column == "p1") {
      EXPECT_EQ(row[c], got[1]);
    }
  }
  // z1's rate is the slope of z1 (trapezoidal rule: the mean of the rates).
  double before = 0.0, after = 0.0, rate_before = 0.0, rate_after = 0.0;
  ASSERT_EQ(mhs_get(sim.get(), &z1, 1, &before), MHS_OK);
  ASSERT_EQ(mhs_get(sim.get(), &rate, 1, &rate_before), MHS_OK);
  ASSERT_TRUE(ok(mhs_step(sim.get())));
  ASSERT_EQ(mhs_get(sim.get(), &z1, 1, &after), MHS_OK);
  ASSERT_EQ(mhs_get(sim.get(), &rate, 1, &rate_after), MHS_OK);
  EXPECT_NEAR((after - before) / 1e-3, 0.5 * (rate_before + rate_after),
              1e-9 * (1.0 + std::abs(rate_after)));
}

// Snapshot at 4 s, run to 10 s, restore, run to 10 s again: the same rows.
void expect_restored_run_repeats(const std::string& name, const std::string& formulation) {
  Sim sim = open(name, {{"formulation", formulation.c_str()}});
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 4.0))) << mhs_message(sim.get());
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
  Snapshot snap(raw);
  ASSERT_EQ(mhs_save(sim.get(), snap.get()), MHS_OK) << mhs_message(sim.get());
  const std::string first = rows_until(sim.get(), 10.0);
  ASSERT_TRUE(ok(mhs_restore(sim.get(), snap.get()))) << mhs_message(sim.get());
  double t = 0.0;
  ASSERT_EQ(mhs_time(sim.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(t, 4.0);
  EXPECT_EQ(rows_until(sim.get(), 10.0), first);
  // And in a fresh run opened alike, restored before it started.
  Sim fresh = open(name, {{"formulation", formulation.c_str()}});
  ASSERT_TRUE(ok(mhs_restore(fresh.get(), snap.get()))) << mhs_message(fresh.get());
  EXPECT_EQ(rows_until(fresh.get(), 10.0), first);
}

TEST(EmbeddingSnapshot, FourBarDoubleStepRestoredAt4sRepeatsTo10sToTheBit) {
  expect_restored_run_repeats("fourbar.yaml", "double-step");
}
TEST(EmbeddingSnapshot, FourBarPenaltyRestoredAt4sRepeatsTo10sToTheBit) {
  expect_restored_run_repeats("fourbar.yaml", "penalty");
}
TEST(EmbeddingSnapshot, ExcavatorRestoredAt4sRepeatsTo10sToTheBit) {
  expect_restored_run_repeats("excavator.yaml", "double-step");
}

TEST(EmbeddingSnapshot, BytesRestoredInANewProcessContinueIdentically) {
  for (const std::string formulation : {"double-step", "penalty"}) {
    Sim sim = open("fourbar.yaml", {{"formulation", formulation.c_str()}});
    ASSERT_TRUE(ok(mhs_advance(sim.get(), 4.0)));
    mhs_snapshot* raw = nullptr;
    ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
    Snapshot snap(raw);
    ASSERT_EQ(mhs_save(sim.get(), snap.get()), MHS_OK);
    const void* bytes = nullptr;
    size_t size = 0;
    ASSERT_EQ(mhs_snapshot_bytes(sim.get(), snap.get(), &bytes, &size), MHS_OK);
    const auto dir = scratch("bytes-" + formulation);
    std::ofstream(dir / "state.bin", std::ios::binary)
        .write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    const std::string here = rows_until(sim.get(), 10.0);
    const std::string command =
        std::string(mh::test::paths::resume_snapshot) + " " + model("fourbar.yaml") + " " +
        formulation + " " + (dir / "state.bin").string() + " 10 > " + (dir / "rows.csv").string();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    EXPECT_EQ(read_text(dir / "rows.csv"), here) << formulation;
  }
}

TEST(EmbeddingThreads, FourInstancesInFourThreadsGiveTheSerialRowsToTheBit) {
  const std::vector<std::vector<mhs_setting>> runs = {
      {{"formulation", "double-step"}, {"t_end", "2"}},
      {{"formulation", "penalty"}, {"t_end", "2"}},
      {{"formulation", "double-step"}, {"t_end", "2"}, {"dt", "0.002"}},
      {{"formulation", "penalty"}, {"t_end", "2"}, {"integrator", "bdf2"}}};
  std::vector<std::string> serial, threaded(runs.size());
  for (const auto& settings : runs) {
    Sim sim = open("quickreturn.yaml", settings);
    serial.push_back(api_csv(sim.get()));
  }
  std::vector<Sim> sims;
  for (const auto& settings : runs) sims.push_back(open("quickreturn.yaml", settings));
  std::vector<std::thread> threads;
  for (size_t k = 0; k < runs.size(); ++k)
    threads.emplace_back([&, k] { threaded[k] = api_csv(sims[k].get()); });
  for (auto& t : threads) t.join();
  for (size_t k = 0; k < runs.size(); ++k) EXPECT_EQ(threaded[k], serial[k]) << "run " << k;
}

// The paper's valve cycle (V) from step k on: what models/fourbar.yaml's
// input table holds.
double paper_cycle(int64_t k) {
  return k >= 8000 ? 0.0 : k >= 5000 ? -10.0 : k >= 2500 ? 0.0 : k >= 1000 ? 10.0 : 0.0;
}
// Another: 5 V from 0.5 s, -5 V from 1.5 s.
double other_cycle(int64_t k) {
  return k >= 1500 ? -5.0 : k >= 500 ? 5.0 : 0.0;
}

// The CSV of a run whose valve_command the caller sets before every step.
std::string driven_csv(mhs_simulation* sim, double (*command)(int64_t)) {
  uint32_t input = 0;
  EXPECT_EQ(mhs_find(sim, "valve_command", &input), MHS_OK) << mhs_message(sim);
  double u = command(0);
  EXPECT_EQ(mhs_set(sim, &input, 1, &u), MHS_OK) << mhs_message(sim);
  std::string csv = row_text(sim, true);
  EXPECT_TRUE(ok(mhs_start(sim))) << mhs_message(sim);
  csv += row_text(sim);
  double t = 0.0, dt = 0.0, t_end = 0.0;
  int64_t k = 0;
  EXPECT_EQ(mhs_time(sim, &t, &k, &dt, &t_end), MHS_OK);
  while (t < t_end - 0.5 * dt) {
    u = command(k);
    EXPECT_EQ(mhs_set(sim, &input, 1, &u), MHS_OK) << mhs_message(sim);
    if (!ok(mhs_step(sim))) {
      ADD_FAILURE() << mhs_message(sim);
      break;
    }
    csv += row_text(sim);
    EXPECT_EQ(mhs_time(sim, &t, &k, nullptr, nullptr), MHS_OK);
  }
  return csv;
}

TEST(EmbeddingInputs, TheValveCommandSetFromCodeIsTheTableItReplacesToTheByte) {
  // Each change of the command is a jump at the step's start, restarting the
  // integrator there as the table's time event did at the same time.
  const std::vector<std::pair<std::string, std::string>> runs = {{"double-step", "trapezoidal"},
                                                                 {"penalty", "trapezoidal"},
                                                                 {"double-step", "bdf2"},
                                                                 {"penalty", "generalized-alpha"}};
  for (const auto& [formulation, integrator] : runs) {
    Sim sim = open(
        "fourbar.yaml",
        {{"formulation", formulation.c_str()}, {"integrator", integrator.c_str()}, {"t_end", "6"}});
    EXPECT_EQ(driven_csv(sim.get(), paper_cycle),
              cli_csv("fourbar.yaml",
                      "--formulation " + formulation + " --integrator " + integrator + " --t-end 6",
                      formulation + "-" + integrator))
        << formulation << " + " << integrator;
  }
}

TEST(EmbeddingInputs, AnotherCycleSetFromCodeIsTheModelWithThatTable) {
  std::string text = read_text(model("fourbar.yaml"));
  const std::string paper =
      "table: [[0, 0], [1, 0], [1, 10], [2.5, 10], [2.5, 0], [5, 0], [5, -10], [8, -10], [8, 0]]";
  ASSERT_NE(text.find(paper), std::string::npos);
  text.replace(text.find(paper), paper.size(),
               "table: [[0, 0], [0.5, 0], [0.5, 5], [1.5, 5], [1.5, -5]]");
  mhs_simulation* raw = nullptr;
  const mhs_setting two_s = {"t_end", "2"};
  ASSERT_LE(mhs_open_text(text.c_str(), "other-cycle.yaml",
                          (std::string(mh::test::paths::source_dir) + "/models").c_str(), &two_s, 1,
                          &raw),
            MHS_WARNING)
      << mhs_message(raw);
  Sim tabled(raw);
  Sim driven = open("fourbar.yaml", {{"t_end", "2"}});
  const std::string by_code = driven_csv(driven.get(), other_cycle);
  EXPECT_EQ(by_code, api_csv(tabled.get()));
  Sim paper_run = open("fourbar.yaml", {{"t_end", "2"}});
  EXPECT_NE(by_code, api_csv(paper_run.get()));
}

TEST(EmbeddingInputs, AnInputIsListedWithItsUnitAndRangeAndReadsItsTableUntilSet) {
  Sim sim = open("fourbar.yaml");
  uint32_t input = 0;
  ASSERT_EQ(mhs_find(sim.get(), "valve_command", &input), MHS_OK);
  mhs_variable_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(mhs_variable(sim.get(), input, &info), MHS_OK);
  EXPECT_EQ(info.kind, MHS_INPUT);
  EXPECT_STREQ(info.unit, "V");
  EXPECT_STREQ(info.qualified, "inputs.valve_command");
  EXPECT_EQ(info.min, -10.0);
  EXPECT_EQ(info.max, 10.0);
  uint32_t count = 0;
  ASSERT_EQ(mhs_variable_count(sim.get(), &count), MHS_OK);
  EXPECT_EQ(input, count - 1);  // the inputs come last
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 1.5)));
  double u = 0.0;
  ASSERT_EQ(mhs_get(sim.get(), &input, 1, &u), MHS_OK);
  EXPECT_EQ(u, 10.0);  // its table's
  const double seven = 7.0;
  ASSERT_EQ(mhs_set(sim.get(), &input, 1, &seven), MHS_OK);
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 3.0)));
  ASSERT_EQ(mhs_get(sim.get(), &input, 1, &u), MHS_OK);
  EXPECT_EQ(u, 7.0);  // held, where the table went to 0 at 2.5 s
  // The spool follows it: U -> 7 V with tau = 4.5 ms, settled after 1.5 s.
  uint32_t spool = 0;
  ASSERT_EQ(mhs_find(sim.get(), "U", &spool), MHS_OK);
  double U = 0.0;
  ASSERT_EQ(mhs_get(sim.get(), &spool, 1, &U), MHS_OK);
  EXPECT_NEAR(U, 7.0, 1e-6);
}

TEST(EmbeddingSnapshot, ASnapshotKeepsTheInputsAndAJumpNotYetStepped) {
  Sim sim = open("fourbar.yaml");
  uint32_t input = 0;
  ASSERT_EQ(mhs_find(sim.get(), "valve_command", &input), MHS_OK);
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 1.2)));
  const double u = -4.0;
  ASSERT_EQ(mhs_set(sim.get(), &input, 1, &u), MHS_OK);  // a jump the next step starts with
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
  Snapshot snap(raw);
  ASSERT_EQ(mhs_save(sim.get(), snap.get()), MHS_OK);
  const std::string first = rows_until(sim.get(), 2.0);
  ASSERT_TRUE(ok(mhs_restore(sim.get(), snap.get())));
  EXPECT_EQ(rows_until(sim.get(), 2.0), first);
  Sim fresh = open("fourbar.yaml");  // its input still follows the table
  ASSERT_TRUE(ok(mhs_restore(fresh.get(), snap.get())));
  EXPECT_EQ(rows_until(fresh.get(), 2.0), first);
  Sim unset = open("fourbar.yaml");
  ASSERT_TRUE(ok(mhs_advance(unset.get(), 1.2)));
  EXPECT_NE(rows_until(unset.get(), 2.0), first);  // the set value mattered
}

TEST(EmbeddingBadCalls, InputsRefuseOtherValuesNaNAndOutOfRangeSettingNone) {
  Sim sim = open("fourbar.yaml");
  uint32_t input = 0, z1 = 0;
  ASSERT_EQ(mhs_find(sim.get(), "valve_command", &input), MHS_OK);
  ASSERT_EQ(mhs_find(sim.get(), "z1", &z1), MHS_OK);
  double v = 1.0;
  EXPECT_EQ(mhs_set(sim.get(), &z1, 1, &v), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()),
               "mhs_set: 'z1' is not an input (only the model's inputs: are set)");
  v = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(mhs_set(sim.get(), &input, 1, &v), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()), "mhs_set: input 'valve_command': nan is not a finite value");
  v = 11.0;
  EXPECT_EQ(mhs_set(sim.get(), &input, 1, &v), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()),
               "mhs_set: input 'valve_command': 11 V is outside its range [-10, 10] "
               "(out_of_range: refuse)");
  const uint32_t both[] = {input, z1};
  const double values[] = {3.0, 0.0};
  EXPECT_EQ(mhs_set(sim.get(), both, 2, values), MHS_ERROR);  // all or nothing
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  double u = 1.0;
  ASSERT_EQ(mhs_get(sim.get(), &input, 1, &u), MHS_OK);
  EXPECT_EQ(u, 0.0);  // still its table's

  // An input that clamps: set to 12 V, it takes 10 V and says so.
  std::string text = read_text(model("fourbar.yaml"));
  const std::string range = "range: [-10, 10]";
  ASSERT_NE(text.find(range), std::string::npos);
  text.replace(text.find(range), range.size(), range + "\n    out_of_range: clamp");
  mhs_simulation* raw = nullptr;
  ASSERT_LE(mhs_open_text(text.c_str(), "clamp.yaml",
                          (std::string(mh::test::paths::source_dir) + "/models").c_str(), nullptr,
                          0, &raw),
            MHS_WARNING)
      << mhs_message(raw);
  Sim clamps(raw);
  ASSERT_TRUE(ok(mhs_start(clamps.get())));
  v = 12.0;
  EXPECT_EQ(mhs_set(clamps.get(), &input, 1, &v), MHS_WARNING);
  EXPECT_STREQ(mhs_message(clamps.get()),
               "mhs_set: input 'valve_command': 12 clamped to 10 (out_of_range: clamp)");
  ASSERT_EQ(mhs_get(clamps.get(), &input, 1, &u), MHS_OK);
  EXPECT_EQ(u, 10.0);
}

// Every call with a NULL handle: MHS_ERROR, and mhs_message(NULL) says so.
TEST(EmbeddingBadCalls, ANullHandleIsRefusedByEveryCall) {
  double d = 0.0;
  uint32_t u = 0;
  int32_t i = 0;
  size_t n = 0;
  const char* s = nullptr;
  const void* b = nullptr;
  mhs_snapshot* snap = nullptr;
  mhs_variable_info info{};
  info.struct_size = sizeof info;
  EXPECT_EQ(mhs_start(nullptr), MHS_ERROR);
  EXPECT_EQ(mhs_step(nullptr), MHS_ERROR);
  EXPECT_EQ(mhs_advance(nullptr, 1.0), MHS_ERROR);
  EXPECT_EQ(mhs_time(nullptr, &d, nullptr, nullptr, nullptr), MHS_ERROR);
  EXPECT_EQ(mhs_variable_count(nullptr, &u), MHS_ERROR);
  EXPECT_EQ(mhs_variable(nullptr, 0, &info), MHS_ERROR);
  EXPECT_EQ(mhs_find(nullptr, "z1", &u), MHS_ERROR);
  EXPECT_EQ(mhs_get(nullptr, &u, 1, &d), MHS_ERROR);
  EXPECT_EQ(mhs_row_size(nullptr, &u), MHS_ERROR);
  EXPECT_EQ(mhs_row_name(nullptr, 0, &s), MHS_ERROR);
  EXPECT_EQ(mhs_row_due(nullptr, &i), MHS_ERROR);
  EXPECT_EQ(mhs_row(nullptr, &d, 1), MHS_ERROR);
  EXPECT_EQ(mhs_row_text(nullptr, 0, nullptr, 0, &n), MHS_ERROR);
  EXPECT_EQ(mhs_snapshot_new(nullptr, &snap), MHS_ERROR);
  EXPECT_EQ(mhs_save(nullptr, snap), MHS_ERROR);
  EXPECT_EQ(mhs_restore(nullptr, snap), MHS_ERROR);
  EXPECT_EQ(mhs_snapshot_bytes(nullptr, snap, &b, &n), MHS_ERROR);
  EXPECT_EQ(mhs_snapshot_read(nullptr, snap, "x", 1), MHS_ERROR);
  EXPECT_STREQ(mhs_message(nullptr), "the simulation handle is NULL");
  mhs_free(nullptr);
  mhs_snapshot_free(nullptr);
  EXPECT_EQ(mhs_open_file("x.yaml", nullptr, 0, nullptr), MHS_ERROR);
}

TEST(EmbeddingBadCalls, AModelThatDoesNotOpenIsFatalAndSaysWhy) {
  mhs_simulation* raw = nullptr;
  EXPECT_EQ(mhs_open_file("/nonexistent/model.yaml", nullptr, 0, &raw), MHS_FATAL);
  Sim missing(raw);
  EXPECT_NE(std::string(mhs_message(missing.get())).find("/nonexistent/model.yaml"),
            std::string::npos)
      << mhs_message(missing.get());
  EXPECT_EQ(mhs_step(missing.get()), MHS_FATAL);
  EXPECT_NE(std::string(mhs_message(missing.get())).find("did not open"), std::string::npos);

  const char* text = "bodies: [{name: b, mass: -1}]\n";
  EXPECT_EQ(mhs_open_text(text, "bad.yaml", nullptr, nullptr, 0, &raw), MHS_FATAL);
  Sim bad(raw);
  EXPECT_NE(std::string(mhs_message(bad.get())).find("bad.yaml"), std::string::npos)
      << mhs_message(bad.get());

  const mhs_setting unknown_path = {"subsystems/nope/flow", "1"};
  EXPECT_EQ(mhs_open_file(model("fourbar.yaml").c_str(), &unknown_path, 1, &raw), MHS_FATAL);
  Sim no_path(raw);
  EXPECT_NE(std::string(mhs_message(no_path.get())).find("subsystems/nope/flow"), std::string::npos)
      << mhs_message(no_path.get());

  const mhs_setting bad_dt = {"dt", "fast"};
  EXPECT_EQ(mhs_open_file(model("fourbar.yaml").c_str(), &bad_dt, 1, &raw), MHS_FATAL);
  Sim no_dt(raw);
  EXPECT_STREQ(mhs_message(no_dt.get()),
               "setting 'dt': 'fast' is not a positive number of seconds");

  const mhs_setting no_value = {"dt", nullptr};
  EXPECT_EQ(mhs_open_file(model("fourbar.yaml").c_str(), &no_value, 1, &raw), MHS_FATAL);
  Sim null_value(raw);
  EXPECT_STREQ(mhs_message(null_value.get()), "setting 0 has a NULL path or value");

  std::string text_model = read_text(model("fourbar.yaml"));
  const std::string reference = "reference: valve_command";
  ASSERT_NE(text_model.find(reference), std::string::npos);
  text_model.replace(text_model.find(reference), reference.size(), "reference: valve_comand");
  EXPECT_EQ(mhs_open_text(text_model.c_str(), "typo.yaml",
                          (std::string(mh::test::paths::source_dir) + "/models").c_str(), nullptr,
                          0, &raw),
            MHS_FATAL);
  Sim typo(raw);
  EXPECT_NE(std::string(mhs_message(typo.get()))
                .find("option 'reference': a table of rows [t (s), value], one of the model's "
                      "inputs (valve_command) or a state 'instance.state' of an instance listed "
                      "above this one, got 'valve_comand'"),
            std::string::npos)
      << mhs_message(typo.get());

  const mhs_setting formulation = {"formulation", "no-such-formulation"};
  EXPECT_EQ(mhs_open_file(model("fourbar.yaml").c_str(), &formulation, 1, &raw), MHS_FATAL);
  Sim unknown(raw);
  EXPECT_NE(std::string(mhs_message(unknown.get())).find("no-such-formulation"), std::string::npos)
      << mhs_message(unknown.get());
}

TEST(EmbeddingBadCalls, UnknownNamesIndicesAndTimesAreRefusedNamingThem) {
  Sim sim = open("fourbar.yaml");
  uint32_t index = 0;
  EXPECT_EQ(mhs_find(sim.get(), "p9", &index), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()),
               "mhs_find: no value is called 'p9' (mhs_variable lists them)");
  double v = 0.0;
  EXPECT_EQ(mhs_get(sim.get(), &index, 1, &v), MHS_ERROR);  // not started
  EXPECT_STREQ(mhs_message(sim.get()), "mhs_get: the run has not started (mhs_start)");
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  EXPECT_EQ(mhs_start(sim.get()), MHS_ERROR);
  const uint32_t beyond = 100000;
  EXPECT_EQ(mhs_get(sim.get(), &beyond, 1, &v), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("100000 is not below"), std::string::npos);
  mhs_variable_info info{};
  info.struct_size = 4;
  EXPECT_EQ(mhs_variable(sim.get(), 0, &info), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("struct_size is 4"), std::string::npos);
  EXPECT_EQ(mhs_advance(sim.get(), std::numeric_limits<double>::quiet_NaN()), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()), "mhs_advance: t = nan is not a finite time");
  EXPECT_EQ(mhs_advance(sim.get(), std::numeric_limits<double>::infinity()), MHS_ERROR);
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 0.5)));
  EXPECT_EQ(mhs_advance(sim.get(), 0.25), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()), "mhs_advance: t = 0.25 s is before the run's time 0.5 s");
  char small[4];
  size_t length = 0;
  EXPECT_EQ(mhs_row_text(sim.get(), 0, small, sizeof small, &length), MHS_ERROR);
  EXPECT_GT(length, sizeof small);
  double t = 0.0;
  ASSERT_EQ(mhs_time(sim.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(t, 0.5);  // nothing refused changed the run
  // The refusal's words stay through the calls that succeed, until the next
  // call that does not.
  EXPECT_NE(std::string(mhs_message(sim.get())).find("mhs_row_text"), std::string::npos)
      << mhs_message(sim.get());
  EXPECT_EQ(mhs_advance(sim.get(), 0.25), MHS_ERROR);
  EXPECT_STREQ(mhs_message(sim.get()), "mhs_advance: t = 0.25 s is before the run's time 0.5 s");
}

TEST(EmbeddingSnapshot, ARestoreIntoAModelWithOtherValuesWarnsNamingThem) {
  Sim sim = open("fourbar.yaml");
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 0.2)));
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
  Snapshot snap(raw);
  ASSERT_EQ(mhs_save(sim.get(), snap.get()), MHS_OK);
  ASSERT_EQ(mhs_restore(sim.get(), snap.get()), MHS_OK);  // the same model: nothing to say
  ASSERT_EQ(mhs_set_parameter(sim.get(), "bodies/body3/mass", 60.0), MHS_OK);
  ASSERT_EQ(mhs_set_parameter(sim.get(), "gravity/1", -9.0), MHS_OK);
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 0.3)));
  EXPECT_EQ(mhs_restore(sim.get(), snap.get()), MHS_WARNING);
  const std::string message = mhs_message(sim.get());
  EXPECT_NE(message.find("body 'body3' mass 60 kg in this run, 50 kg in the snapshot"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("gravity y -9 m/s^2 in this run, -9.81 m/s^2 in the snapshot"),
            std::string::npos)
      << message;
  double t = 0.0;
  ASSERT_EQ(mhs_time(sim.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_NEAR(t, 0.2, 1e-12);  // restored, as the changed model
  // The same through bytes, as another process would restore them.
  const void* bytes = nullptr;
  size_t size = 0;
  ASSERT_EQ(mhs_snapshot_bytes(sim.get(), snap.get(), &bytes, &size), MHS_OK);
  std::vector<unsigned char> copy(static_cast<const unsigned char*>(bytes),
                                  static_cast<const unsigned char*>(bytes) + size);
  ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
  Snapshot read(raw);
  ASSERT_EQ(mhs_snapshot_read(sim.get(), read.get(), copy.data(), copy.size()), MHS_OK);
  EXPECT_EQ(mhs_restore(sim.get(), read.get()), MHS_WARNING);
  // Set back, nothing to say.
  ASSERT_EQ(mhs_set_parameter(sim.get(), "bodies/body3/mass", 50.0), MHS_OK);
  ASSERT_EQ(mhs_set_parameter(sim.get(), "gravity/1", -9.81), MHS_OK);
  EXPECT_EQ(mhs_restore(sim.get(), read.get()), MHS_OK) << mhs_message(sim.get());
}

TEST(EmbeddingThreads, ASecondThreadsCallOnABusyRunIsRefusedAndChangesNothing) {
  Sim sim = open("fourbar.yaml");
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  // One long call in another thread (days of model time, until cancelled);
  // tried again when this thread's call refused it.
  std::thread stepping([&] {
    while (mhs_advance(sim.get(), 1e6) == MHS_ERROR) {
    }
  });
  // This thread's calls go through until the other's call begins, then
  // each is refused whole with its own message.
  int refused = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (refused == 0 && std::chrono::steady_clock::now() < until) {
    double t = -1.0;
    const mhs_status st = mhs_time(sim.get(), &t, nullptr, nullptr, nullptr);
    if (st == MHS_OK) continue;
    ++refused;
    EXPECT_EQ(st, MHS_ERROR);
    EXPECT_EQ(t, -1.0);  // nothing written
    EXPECT_NE(std::string(mhs_message(sim.get())).find("another thread is in a call"),
              std::string::npos)
        << mhs_message(sim.get());
  }
  mhs_cancel(sim.get());
  stepping.join();
  EXPECT_EQ(refused, 1);
  // Alone again: calls go through, and the message is the run's own (the
  // other thread's cancelled advance, cancelled before or after its first
  // step: a slow machine may not have taken one).
  double t = -1.0;
  EXPECT_EQ(mhs_time(sim.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_GE(t, 0.0);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("cancelled"), std::string::npos)
      << mhs_message(sim.get());
}

TEST(EmbeddingThreads, CancelEndsALongAdvanceBetweenTwoStepsAndTheRunGoesOn) {
  Sim sim = open("fourbar.yaml");
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    mhs_cancel(sim.get());
  });
  const mhs_status st = mhs_advance(sim.get(), 1e6);  // days of model time
  canceller.join();
  EXPECT_EQ(st, MHS_DISCARD);
  const std::string message = mhs_message(sim.get());
  EXPECT_NE(message.find("mhs_advance: cancelled (mhs_cancel) at t = "), std::string::npos)
      << message;
  double t = 0.0, dt = 0.0;
  int64_t steps = 0;
  ASSERT_EQ(mhs_time(sim.get(), &t, &steps, &dt, nullptr), MHS_OK);
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 1e3);
  EXPECT_NEAR(t, static_cast<double>(steps) * dt, 1e-9);  // at a step
  EXPECT_EQ(mhs_advance(sim.get(), t + 0.01), MHS_OK) << mhs_message(sim.get());
  // A cancel with no call in flight ends the next one at its start.
  mhs_cancel(sim.get());
  EXPECT_EQ(mhs_advance(sim.get(), t + 0.02), MHS_DISCARD);
  double after = 0.0;
  ASSERT_EQ(mhs_time(sim.get(), &after, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_NEAR(after, t + 0.01, 1e-9);
  EXPECT_EQ(mhs_advance(sim.get(), t + 0.02), MHS_OK);
  mhs_cancel(nullptr);  // ignored
}

TEST(EmbeddingBadCalls, AFailedStepStopsTheRunAndItsMessageStaysUntilASnapshotIsRestored) {
  // One Newton iteration a step and no halving: the run fails once the
  // valve opens and a step needs a second iteration.
  Sim sim =
      open("fourbar.yaml", {{"solver/max_iterations", "1"}, {"solver/max_step_halvings", "0"}});
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(sim.get(), &raw), MHS_OK);
  Snapshot start(raw);
  ASSERT_EQ(mhs_save(sim.get(), start.get()), MHS_OK);
  ASSERT_EQ(mhs_advance(sim.get(), 10.0), MHS_ERROR);
  const std::string why = mhs_message(sim.get());
  EXPECT_EQ(why.rfind("t = 1.001 s, step 1001: Newton did not converge in 1 iterations", 0), 0u)
      << why;
  double t = 0.0;
  int64_t steps = 0;
  ASSERT_EQ(mhs_time(sim.get(), &t, &steps, nullptr, nullptr), MHS_OK);
  EXPECT_GT(t, 0.0);  // the last accepted state, before the failed step
  EXPECT_LT(t, 10.0);
  EXPECT_EQ(mhs_step(sim.get()), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("takes no step after a failed one"),
            std::string::npos);
  EXPECT_EQ(mhs_advance(sim.get(), 10.0), MHS_ERROR);
  int64_t still = 0;
  ASSERT_EQ(mhs_time(sim.get(), nullptr, &still, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(still, steps);
  // The refusal's words outlast the calls that succeed after it.
  EXPECT_NE(std::string(mhs_message(sim.get())).find("takes no step after a failed one"),
            std::string::npos)
      << mhs_message(sim.get());
  // Restored, it steps again, and fails at the same step for the same reason.
  ASSERT_TRUE(ok(mhs_restore(sim.get(), start.get())));
  EXPECT_STREQ(mhs_message(sim.get()), "");  // gone with the failure
  ASSERT_EQ(mhs_time(sim.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(t, 0.0);
  EXPECT_EQ(mhs_advance(sim.get(), 10.0), MHS_ERROR);
  EXPECT_EQ(std::string(mhs_message(sim.get())), why);
  ASSERT_EQ(mhs_time(sim.get(), nullptr, &still, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(still, steps);
}

TEST(EmbeddingBadCalls, ASnapshotOfAnotherModelOrDamagedBytesIsRefusedLeavingTheRun) {
  Sim fourbar = open("fourbar.yaml");
  Sim quick = open("quickreturn.yaml");
  ASSERT_TRUE(ok(mhs_advance(quick.get(), 0.1)));
  ASSERT_TRUE(ok(mhs_advance(fourbar.get(), 0.2)));
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(quick.get(), &raw), MHS_OK);
  Snapshot snap(raw);
  EXPECT_EQ(mhs_restore(fourbar.get(), snap.get()), MHS_ERROR);
  EXPECT_STREQ(mhs_message(fourbar.get()), "mhs_restore: the snapshot holds no state yet");
  ASSERT_EQ(mhs_save(quick.get(), snap.get()), MHS_OK);
  EXPECT_EQ(mhs_restore(fourbar.get(), snap.get()), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(fourbar.get())).find("not one of this run"), std::string::npos)
      << mhs_message(fourbar.get());

  const void* bytes = nullptr;
  size_t size = 0;
  ASSERT_EQ(mhs_snapshot_bytes(quick.get(), snap.get(), &bytes, &size), MHS_OK);
  const std::string good(static_cast<const char*>(bytes), size);
  mhs_snapshot* raw2 = nullptr;
  ASSERT_EQ(mhs_snapshot_new(quick.get(), &raw2), MHS_OK);
  Snapshot copy(raw2);
  const auto refused = [&](std::string damaged, const std::string& words) {
    EXPECT_EQ(mhs_snapshot_read(quick.get(), copy.get(), damaged.data(), damaged.size()),
              MHS_ERROR);
    EXPECT_NE(std::string(mhs_message(quick.get())).find(words), std::string::npos)
        << mhs_message(quick.get());
    EXPECT_EQ(mhs_restore(quick.get(), copy.get()), MHS_ERROR);  // it holds nothing
  };
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  refused(flipped, "checksum does not match");
  refused(good.substr(0, good.size() - 9), "cut short or run on");
  refused(good + "x", "cut short or run on");
  refused("hello", "not a monohydra run state");
  refused("", "not a monohydra run state");
  std::string version = good;
  version[8] = 9;
  refused(version, "format version 9");
  // The good bytes still restore, and the run goes on as the saved one.
  ASSERT_EQ(mhs_snapshot_read(quick.get(), copy.get(), good.data(), good.size()), MHS_OK);
  const std::string after = rows_until(quick.get(), 0.2);
  ASSERT_TRUE(ok(mhs_restore(quick.get(), copy.get())));
  EXPECT_EQ(rows_until(quick.get(), 0.2), after);
  double t = 0.0;
  ASSERT_EQ(mhs_time(fourbar.get(), &t, nullptr, nullptr, nullptr), MHS_OK);
  EXPECT_EQ(t, 0.2);
}

TEST(EmbeddingBadCalls, TheApiVersionIsTheHeadersMajor) {
  EXPECT_EQ(mhs_api_version() >> 16, MHS_API_VERSION_MAJOR);
  EXPECT_EQ(mhs_api_version() & 0xffffu, MHS_API_VERSION_MINOR);
}

}  // namespace

namespace {

struct FreeLinearization {
  void operator()(mhs_linearization* l) const { mhs_linearization_free(l); }
};
using Linearization = std::unique_ptr<mhs_linearization, FreeLinearization>;

uint32_t find(mhs_simulation* sim, const char* name) {
  uint32_t index = 0;
  EXPECT_EQ(mhs_find(sim, name, &index), MHS_OK) << name << ": " << mhs_message(sim);
  return index;
}

TEST(EmbeddingLinearization, FourbarMatricesHaveTheirSizesNamesAndTheSpoolsTimeConstant) {
  Sim sim = open("fourbar.yaml");
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  ASSERT_TRUE(ok(mhs_advance(sim.get(), 0.5))) << mhs_message(sim.get());
  const uint32_t outputs[] = {find(sim.get(), "s"), find(sim.get(), "z1_dot"),
                              find(sim.get(), "U")};
  mhs_linearization* raw = nullptr;
  ASSERT_EQ(mhs_linearize(sim.get(), outputs, 3, &raw), MHS_OK) << mhs_message(sim.get());
  const Linearization lin(raw);
  uint32_t n = 0, m = 0, p = 0;
  double t = 0.0;
  ASSERT_EQ(mhs_linearization_size(sim.get(), lin.get(), &n, &m, &p, &t), MHS_OK);
  EXPECT_EQ(m, 1u);
  EXPECT_EQ(p, 3u);
  EXPECT_NEAR(t, 0.5, 1e-12);
  const char* name = nullptr;
  const char* unit = nullptr;
  ASSERT_EQ(mhs_linearization_name(sim.get(), lin.get(), MHS_LINEAR_INPUT, 0, &name, &unit),
            MHS_OK);
  EXPECT_STREQ(name, "valve_command");
  EXPECT_STREQ(unit, "V");
  ASSERT_EQ(mhs_linearization_name(sim.get(), lin.get(), MHS_LINEAR_OUTPUT, 1, &name, &unit),
            MHS_OK);
  EXPECT_STREQ(name, "z1_dot");
  EXPECT_STREQ(unit, "rad/s");
  int spool = -1;
  for (uint32_t k = 0; k < n; ++k) {
    ASSERT_EQ(mhs_linearization_name(sim.get(), lin.get(), MHS_LINEAR_STATE, k, &name, &unit),
              MHS_OK);
    if (std::string(name) == "U") spool = static_cast<int>(k);
  }
  ASSERT_GE(spool, 0);
  std::vector<double> a(n * n), b(n * m), c(p * n), d(p * m);
  ASSERT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'A', a.data(), a.size()), MHS_OK);
  ASSERT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'B', b.data(), b.size()), MHS_OK);
  ASSERT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'C', c.data(), c.size()), MHS_OK);
  ASSERT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'D', d.data(), d.size()), MHS_OK);
  const double tau = 4.547e-3;  // the model's spool time constant
  const auto s = static_cast<size_t>(spool);
  EXPECT_NEAR(a[s + s * n], -1.0 / tau, 1e-4 / tau);  // column-major
  EXPECT_NEAR(b[s], 1.0 / tau, 1e-4 / tau);
  EXPECT_NEAR(c[2 + s * p], 1.0, 1e-6);  // output U is the state U
  // Too small a buffer, an unknown matrix: refused, named.
  EXPECT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'A', a.data(), a.size() - 1), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("entries"), std::string::npos);
  EXPECT_EQ(mhs_linearization_matrix(sim.get(), lin.get(), 'E', a.data(), a.size()), MHS_ERROR);
  EXPECT_EQ(mhs_linearization_name(sim.get(), lin.get(), MHS_LINEAR_STATE, n, &name, &unit),
            MHS_ERROR);
  // The run goes on.
  EXPECT_TRUE(ok(mhs_step(sim.get()))) << mhs_message(sim.get());
}

TEST(EmbeddingLinearization, RefusesNullHandlesUnknownIndicesInputsAndARunNotStarted) {
  mhs_linearization* out = nullptr;
  EXPECT_EQ(mhs_linearize(nullptr, nullptr, 0, &out), MHS_ERROR);
  EXPECT_EQ(out, nullptr);
  Sim sim = open("fourbar.yaml");
  EXPECT_EQ(mhs_linearize(sim.get(), nullptr, 0, &out), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("not started"), std::string::npos)
      << mhs_message(sim.get());
  ASSERT_TRUE(ok(mhs_start(sim.get())));
  EXPECT_EQ(mhs_linearize(sim.get(), nullptr, 0, nullptr), MHS_ERROR);
  EXPECT_EQ(mhs_linearize(sim.get(), nullptr, 2, &out), MHS_ERROR);
  const uint32_t unknown[] = {1000000u};
  EXPECT_EQ(mhs_linearize(sim.get(), unknown, 1, &out), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("1000000"), std::string::npos);
  const uint32_t input[] = {find(sim.get(), "valve_command")};
  EXPECT_EQ(mhs_linearize(sim.get(), input, 1, &out), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("valve_command"), std::string::npos);
  EXPECT_EQ(out, nullptr);
  EXPECT_EQ(mhs_linearization_size(sim.get(), nullptr, nullptr, nullptr, nullptr, nullptr),
            MHS_ERROR);
  double value = 0.0;
  EXPECT_EQ(mhs_linearization_matrix(sim.get(), nullptr, 'A', &value, 1), MHS_ERROR);
  mhs_linearization_free(nullptr);  // ignored
}

}  // namespace

namespace {

// The values of every coordinate, rate and state of the accepted state.
std::vector<double> motion(mhs_simulation* sim) {
  uint32_t count = 0;
  EXPECT_EQ(mhs_variable_count(sim, &count), MHS_OK);
  std::vector<uint32_t> indices;
  for (uint32_t i = 0; i < count; ++i) {
    mhs_variable_info info{};
    info.struct_size = sizeof info;
    EXPECT_EQ(mhs_variable(sim, i, &info), MHS_OK);
    if (info.kind == MHS_COORDINATE || info.kind == MHS_COORDINATE_RATE || info.kind == MHS_STATE)
      indices.push_back(i);
  }
  std::vector<double> values(indices.size());
  EXPECT_EQ(mhs_get(sim, indices.data(), indices.size(), values.data()), MHS_OK);
  return values;
}

// One column of the row at the accepted state, by name.
double row_value(mhs_simulation* sim, const std::string& column) {
  uint32_t columns = 0;
  EXPECT_EQ(mhs_row_size(sim, &columns), MHS_OK);
  std::vector<double> row(columns);
  EXPECT_EQ(mhs_row(sim, row.data(), row.size()), MHS_OK) << mhs_message(sim);
  for (uint32_t c = 0; c < columns; ++c) {
    const char* name = nullptr;
    EXPECT_EQ(mhs_row_name(sim, c, &name), MHS_OK);
    if (column == name) return row[c];
  }
  ADD_FAILURE() << "no column " << column;
  return std::nan("");
}

void advance_to(mhs_simulation* sim, double t) {
  ASSERT_TRUE(ok(mhs_advance(sim, t))) << mhs_message(sim);
}

}  // namespace

TEST(EmbeddingParameters, AMassSetBeforeStartIsTheModelOpenedWithItToTheByte) {
  Sim sim = open("fourbar.yaml", {{"t_end", "1"}});
  ASSERT_EQ(mhs_set_parameter(sim.get(), "bodies/body3/mass", 57.5), MHS_OK)
      << mhs_message(sim.get());
  ASSERT_EQ(mhs_set_parameter(sim.get(), "gravity/1", -9.80665), MHS_OK) << mhs_message(sim.get());
  EXPECT_EQ(api_csv(sim.get()),
            cli_csv("fourbar.yaml",
                    "--t-end 1 --set bodies/body3/mass=57.5 --set gravity/1=-9.80665", "set"));
}

// A component's option it changes in place (the valve's flow coefficient,
// the cylinder's piston diameter) set before start: the model opened with
// them, to the byte; one it does not change, and a value out of its range,
// refused naming why, nothing changed.
TEST(EmbeddingParameters, AComponentsOptionSetBeforeStartIsTheModelOpenedWithItToTheByte) {
  Sim sim = open("fourbar.yaml", {{"t_end", "1"}});
  ASSERT_EQ(mhs_set_parameter(sim.get(), "subsystems/valve/flow_coefficient", 2.5e-8), MHS_OK)
      << mhs_message(sim.get());
  ASSERT_EQ(mhs_set_parameter(sim.get(), "subsystems/cylinder/piston_diameter", 0.085), MHS_OK)
      << mhs_message(sim.get());
  EXPECT_EQ(mhs_set_parameter(sim.get(), "subsystems/cylinder/length", 1.2), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get()))
                .find("subsystem 'cylinder' (cylinder) does not change 'length' in place"),
            std::string::npos)
      << mhs_message(sim.get());
  EXPECT_EQ(mhs_set_parameter(sim.get(), "subsystems/V1/bulk_modulus", -1.0), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("bulk_modulus: -1 is outside the values"),
            std::string::npos)
      << mhs_message(sim.get());
  EXPECT_EQ(api_csv(sim.get()),
            cli_csv("fourbar.yaml",
                    "--t-end 1 --set subsystems/valve/flow_coefficient=2.5e-8 --set "
                    "subsystems/cylinder/piston_diameter=0.085",
                    "set-options"));
}

// An entry of a component's table (a table valve's flow at its widest
// opening, flow_table/ROW/2) set before start: the model opened with it, to
// the byte, and not the model without it.
TEST(EmbeddingParameters, AnEntryOfAComponentsTableSetBeforeStartIsTheModelOpenedWithIt) {
  std::string text = read_text(model("fourbar.yaml"));
  const auto swap = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  swap("type: valve-4-3", "type: valve-table");
  swap("flow_coefficient: 2.138e-8", "flow_table: [[5, 1e6, 1.069e-4], [10, 1e6, 2.138e-4]]");
  const std::string file = (scratch("table-valve") / "fourbar-table.yaml").string();
  std::ofstream(file) << text;
  const auto csv = [&](const char* path, double value) {
    mhs_simulation* raw = nullptr;
    const mhs_setting end{"t_end", "1.5"};
    EXPECT_LE(mhs_open_file(file.c_str(), &end, 1, &raw), MHS_WARNING) << mhs_message(raw);
    const Sim sim(raw);
    if (path != nullptr) {
      EXPECT_EQ(mhs_set_parameter(sim.get(), path, value), MHS_OK) << mhs_message(sim.get());
    }
    return api_csv(sim.get());
  };
  const std::string changed = csv("subsystems/valve/flow_table/1/2", 2.5e-4);
  const auto out = scratch("cli-table") / "run.csv";
  const std::string command = std::string(mh::test::paths::executable) + " run " + file +
                              " --t-end 1.5 --set subsystems/valve/flow_table/1/2=2.5e-4 --out " +
                              out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(changed, read_text(out));
  EXPECT_NE(changed, csv(nullptr, 0.0));
}

// Between steps: the run goes on as the model opened with the new mass and
// restored from the state the change was made at (the hydraulics included).
TEST(EmbeddingParameters, AMassChangedBetweenStepsGoesOnAsTheChangedModelFromTheSameState) {
  Sim changed = open("fourbar.yaml");
  advance_to(changed.get(), 2.0);
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(changed.get(), &raw), MHS_OK);
  const Snapshot at2(raw);
  ASSERT_EQ(mhs_save(changed.get(), at2.get()), MHS_OK) << mhs_message(changed.get());
  const std::vector<double> before = motion(changed.get());
  ASSERT_EQ(mhs_set_parameter(changed.get(), "bodies/body3/mass", 80.0), MHS_OK)
      << mhs_message(changed.get());
  EXPECT_EQ(motion(changed.get()), before);  // the state itself does not jump
  advance_to(changed.get(), 4.0);

  Sim reopened = open("fourbar.yaml", {{"bodies/body3/mass", "80"}});
  // Restored into the other model on purpose: the restore says so.
  ASSERT_EQ(mhs_restore(reopened.get(), at2.get()), MHS_WARNING) << mhs_message(reopened.get());
  EXPECT_NE(std::string(mhs_message(reopened.get())).find("mass 80 kg in this run"),
            std::string::npos)
      << mhs_message(reopened.get());
  advance_to(reopened.get(), 4.0);
  EXPECT_EQ(motion(changed.get()), motion(reopened.get()));

  Sim nominal = open("fourbar.yaml");
  advance_to(nominal.get(), 4.0);
  EXPECT_NE(motion(changed.get()), motion(nominal.get()));  // and the mass acts
}

// A load picked up between steps (the excavator's bucket takes 1800 kg of
// soil at 0.5 s): the run goes on as the model opened with the load and
// restored from the state it was picked up at, and the load acts.
TEST(EmbeddingParameters, ALoadPickedUpBetweenStepsGoesOnAsTheLoadedModelFromTheSameState) {
  Sim changed = open("excavator.yaml", {{"t_end", "1"}});
  advance_to(changed.get(), 0.5);
  mhs_snapshot* raw = nullptr;
  ASSERT_EQ(mhs_snapshot_new(changed.get(), &raw), MHS_OK);
  const Snapshot at(raw);
  ASSERT_EQ(mhs_save(changed.get(), at.get()), MHS_OK) << mhs_message(changed.get());
  ASSERT_EQ(mhs_set_parameter(changed.get(), "bodies/bucket/payload/mass", 1800.0), MHS_OK)
      << mhs_message(changed.get());
  advance_to(changed.get(), 1.0);

  Sim reopened = open("excavator.yaml", {{"t_end", "1"}, {"bodies/bucket/payload/mass", "1800"}});
  ASSERT_EQ(mhs_restore(reopened.get(), at.get()), MHS_WARNING) << mhs_message(reopened.get());
  advance_to(reopened.get(), 1.0);
  // Within the steps' Newton tolerances (the rates agree to 4e-10 of
  // themselves), not to the bit as the four-bar's mass above: what the run
  // that went on keeps beyond its snapshot is not found yet.
  const std::vector<double> a = motion(changed.get()), b = motion(reopened.get());
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i], b[i], 1e-8 * std::max(std::abs(a[i]), 1.0)) << "value " << i;

  Sim empty = open("excavator.yaml", {{"t_end", "1"}});
  advance_to(empty.get(), 1.0);
  EXPECT_NE(motion(changed.get()), motion(empty.get()));
}

// Under gravity alone a uniform beam's motion does not depend on its mass:
// both links made three times heavier mid-run move on as before, and the
// energy balance's references follow the jump, so drift stays the
// integration's. One link alone changes the motion.
TEST(EmbeddingParameters, ScalingEveryMassMidRunLeavesAPendulumsMotionAndItsDriftAlone) {
  Sim nominal = open("double-pendulum.yaml");
  Sim scaled = open("double-pendulum.yaml");
  Sim one = open("double-pendulum.yaml");
  for (auto* sim : {nominal.get(), scaled.get(), one.get()}) advance_to(sim, 1.0);
  const double drift_before = row_value(scaled.get(), "drift");
  ASSERT_EQ(mhs_set_parameter(scaled.get(), "bodies/link1/mass", 3.0), MHS_OK);
  ASSERT_EQ(mhs_set_parameter(scaled.get(), "bodies/link2/mass", 3.0), MHS_OK);
  ASSERT_EQ(mhs_set_parameter(one.get(), "bodies/link2/mass", 3.0), MHS_OK);
  EXPECT_NEAR(row_value(scaled.get(), "drift"), drift_before, 1e-12);
  for (auto* sim : {nominal.get(), scaled.get(), one.get()}) advance_to(sim, 2.0);
  const std::vector<double> a = motion(nominal.get());
  const std::vector<double> b = motion(scaled.get());
  const std::vector<double> c = motion(one.get());
  ASSERT_EQ(a.size(), b.size());
  double largest = 0.0, one_link = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    largest = std::max(largest, std::abs(a[i] - b[i]));
    one_link = std::max(one_link, std::abs(a[i] - c[i]));
  }
  EXPECT_LT(largest, 1e-9);
  EXPECT_GT(one_link, 1e-2);
  // Drift from the nominal run's, three times over (every energy scaled).
  EXPECT_NEAR(row_value(scaled.get(), "drift") - drift_before,
              3.0 * (row_value(nominal.get(), "drift") - drift_before), 1e-6);
}

// g four times larger and dt half: the same dimensionless scheme, so the
// same path at twice the speed (z'(t) = z(2t)).
TEST(EmbeddingParameters, FourTimesTheGravityRunsAPendulumsPathAtTwiceTheSpeed) {
  Sim nominal = open("double-pendulum.yaml", {{"dt", "0.001"}});
  Sim strong = open("double-pendulum.yaml", {{"dt", "0.0005"}});
  ASSERT_EQ(mhs_set_parameter(strong.get(), "gravity/1", -4 * 9.81), MHS_OK)
      << mhs_message(strong.get());
  advance_to(nominal.get(), 1.0);
  advance_to(strong.get(), 0.5);
  uint32_t z1 = 0, z2 = 0;
  ASSERT_EQ(mhs_find(nominal.get(), "z1", &z1), MHS_OK);
  ASSERT_EQ(mhs_find(nominal.get(), "z2", &z2), MHS_OK);
  for (const uint32_t i : {z1, z2}) {
    double a = 0.0, b = 0.0;
    ASSERT_EQ(mhs_get(nominal.get(), &i, 1, &a), MHS_OK);
    ASSERT_EQ(mhs_get(strong.get(), &i, 1, &b), MHS_OK);
    EXPECT_NEAR(a, b, 1e-8);
    EXPECT_GT(std::abs(a), 0.1);
  }
}

// The quick-return's crank (held at assembly) started 5 degrees further on:
// the loops closed again around it, the run that of the model opened with
// it to round-off (the cylinder took its chamber lengths at the nominal
// start, which its equations cancel), not the nominal run; after the start
// refused, naming why, and the run goes on as it was.
TEST(EmbeddingParameters, AnInitialAngleSetBeforeStartIsTheModelOpenedWithIt) {
  Sim set = open("quickreturn.yaml");
  ASSERT_EQ(mhs_set_parameter(set.get(), "bodies/crank/z0", 35.59), MHS_OK)
      << mhs_message(set.get());
  Sim opened = open("quickreturn.yaml", {{"bodies/crank/z0", "35.59"}});
  Sim nominal = open("quickreturn.yaml");
  for (auto* sim : {set.get(), opened.get(), nominal.get()}) advance_to(sim, 1.0);
  const std::vector<double> a = motion(set.get());
  const std::vector<double> b = motion(opened.get());
  const std::vector<double> c = motion(nominal.get());
  ASSERT_EQ(a.size(), b.size());
  double apart = 0.0, from_nominal = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double size = std::max(std::abs(b[i]), 1.0);
    apart = std::max(apart, std::abs(a[i] - b[i]) / size);
    from_nominal = std::max(from_nominal, std::abs(c[i] - b[i]) / size);
  }
  EXPECT_LT(apart, 1e-9);
  EXPECT_GT(from_nominal, 1e-3);

  EXPECT_EQ(mhs_set_parameter(set.get(), "bodies/crank/z0", 30.59), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(set.get()))
                .find("body 'crank': an initial coordinate changes only before the run starts"),
            std::string::npos)
      << mhs_message(set.get());
  for (auto* sim : {set.get(), opened.get()}) advance_to(sim, 1.5);
  EXPECT_EQ(motion(set.get()).size(), motion(opened.get()).size());
  const std::vector<double> a2 = motion(set.get());
  const std::vector<double> b2 = motion(opened.get());
  for (size_t i = 0; i < a2.size(); ++i)
    EXPECT_NEAR(a2[i], b2[i], 1e-9 * std::max(std::abs(b2[i]), 1.0)) << i;
}

TEST(EmbeddingParameters, WhatCannotChangeInPlaceIsRefusedNamingItAndNothingChanges) {
  Sim sim = open("fourbar.yaml");
  Sim nominal = open("fourbar.yaml");
  advance_to(sim.get(), 0.5);
  advance_to(nominal.get(), 0.5);
  const auto refusal = [&](const char* path, double value) {
    EXPECT_EQ(mhs_set_parameter(sim.get(), path, value), MHS_ERROR) << path;
    return std::string(mhs_message(sim.get()));
  };
  EXPECT_NE(refusal("solver/dt", 1e-4).find("solver/dt: not a value that changes during a run"),
            std::string::npos);
  EXPECT_NE(refusal("subsystems/cylinder/length", 1.2)
                .find("subsystems/cylinder/length: subsystem 'cylinder' (cylinder) does not "
                      "change 'length' in place (its parameters: piston_diameter"),
            std::string::npos);
  EXPECT_NE(refusal("bodies/body9/mass", 1.0).find("no item named 'body9' in bodies"),
            std::string::npos);
  EXPECT_NE(refusal("bodies/body3/mass", -1.0).find("bodies[2].mass: expected a positive"),
            std::string::npos);
  EXPECT_NE(refusal("gravity/1", std::nan("")).find("expected a finite value"), std::string::npos);
  EXPECT_EQ(mhs_set_parameter(sim.get(), nullptr, 1.0), MHS_ERROR);
  EXPECT_EQ(mhs_set_parameter(nullptr, "gravity/1", 1.0), MHS_ERROR);
  advance_to(sim.get(), 1.0);
  advance_to(nominal.get(), 1.0);
  EXPECT_EQ(motion(sim.get()), motion(nominal.get()));
}

// Forward sensitivities through the API: d(p1)/d(mass) and d(z1)/d(supply
// pressure) after 1.5 s against the difference of two runs with the value
// set by mhs_set_parameter, and refused when asked wrongly.
TEST(EmbeddingSensitivities, TrackedDerivativesAgreeWithTwoRunsWithTheValueSet) {
  Sim sim = open("fourbar.yaml");
  const char* paths[] = {"bodies/body3/mass", "subsystems/pump/pressure"};
  ASSERT_EQ(mhs_track_sensitivities(sim.get(), paths, 2), MHS_OK) << mhs_message(sim.get());
  advance_to(sim.get(), 1.5);
  const uint32_t indices[] = {find(sim.get(), "p1"), find(sim.get(), "z1")};
  double d[4] = {};
  ASSERT_EQ(mhs_get_sensitivities(sim.get(), indices, 2, d), MHS_OK) << mhs_message(sim.get());
  const auto value_after = [&](const char* path, double value, uint32_t index) {
    Sim run = open("fourbar.yaml");
    EXPECT_EQ(mhs_set_parameter(run.get(), path, value), MHS_OK) << mhs_message(run.get());
    advance_to(run.get(), 1.5);
    double v = 0.0;
    EXPECT_EQ(mhs_get(run.get(), &index, 1, &v), MHS_OK);
    return v;
  };
  const double dm = 0.05, dp = 1e3;
  const double dp1_dm = (value_after(paths[0], 50.0 + dm, indices[0]) -
                         value_after(paths[0], 50.0 - dm, indices[0])) /
                        (2 * dm);
  const double dz1_dp = (value_after(paths[1], 7.6e6 + dp, indices[1]) -
                         value_after(paths[1], 7.6e6 - dp, indices[1])) /
                        (2 * dp);
  EXPECT_NEAR(d[0], dp1_dm, 1e-3 * std::abs(dp1_dm));
  EXPECT_NEAR(d[3], dz1_dp, 1e-3 * std::abs(dz1_dp));
  EXPECT_GT(std::abs(dz1_dp), 0.0);
}

TEST(EmbeddingSensitivities, AskingWronglyIsRefusedNamingWhy) {
  Sim sim = open("fourbar.yaml");
  const uint32_t index = find(sim.get(), "p1");
  double d = 0.0;
  EXPECT_EQ(mhs_get_sensitivities(sim.get(), &index, 1, &d), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("no parameters are tracked"),
            std::string::npos);
  const char* bad[] = {"subsystems/cylinder/length"};
  EXPECT_EQ(mhs_track_sensitivities(sim.get(), bad, 1), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("does not change 'length' in place"),
            std::string::npos)
      << mhs_message(sim.get());
  EXPECT_EQ(mhs_track_sensitivities(sim.get(), nullptr, 0), MHS_ERROR);
  const char* good[] = {"gravity/1"};
  advance_to(sim.get(), 0.01);
  EXPECT_EQ(mhs_track_sensitivities(sim.get(), good, 1), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(sim.get())).find("before it"), std::string::npos)
      << mhs_message(sim.get());
}
