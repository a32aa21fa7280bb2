// The embedding API's estimator (monohydra/simulation.h 1.4) through the C
// header, as a program that tracks a machine uses it: fed the readings of
// `monohydra estimate`'s data, it gives that command's estimates; its noise
// is set by name; every bad call returns a status and a message naming it,
// and a filter that stopped takes no more readings.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "monohydra/simulation.h"

namespace {

namespace fs = std::filesystem;

struct Free {
  void operator()(mhs_simulation* s) const { mhs_free(s); }
  void operator()(mhs_estimator* e) const { mhs_estimator_free(e); }
};
using Sim = std::unique_ptr<mhs_simulation, Free>;
using Est = std::unique_ptr<mhs_estimator, Free>;

const std::string kFourbar = std::string(mh::test::paths::source_dir) + "/models/fourbar.yaml";
const std::string kCli = mh::test::paths::executable;

fs::path scratch(const std::string& name) {
  const auto dir = fs::path(mh::test::paths::binary_dir) / "test-scratch" / "estimator" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Sim open_fourbar() {
  mhs_simulation* sim = nullptr;
  EXPECT_LE(mhs_open_file(kFourbar.c_str(), nullptr, 0, &sim), MHS_WARNING) << mhs_message(sim);
  return Sim(sim);
}

// A CSV's header and rows; an empty field is NaN.
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  size_t column(const std::string& name) const {
    for (size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) return c;
    return names.size();
  }
};

Table read_table(const fs::path& path) {
  Table t;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) t.names.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    for (size_t c = 0; c < t.names.size(); ++c) {
      if (!std::getline(ss, cell, ',')) cell.clear();
      row.push_back(cell.empty() ? NAN : std::stod(cell));
    }
    t.rows.push_back(row);
  }
  return t;
}

// The four-bar with a heavier load and more friction, read by its sensors
// over `t_end` s, and `monohydra estimate`'s estimates of it with `args`.
void machine_and_command(const fs::path& dir, double t_end, const std::string& args) {
  const std::string run = kCli + " run " + kFourbar +
                          " --set bodies/body3/mass=55 --set subsystems/cylinder/efficiency=0.76" +
                          " --t-end " + std::to_string(t_end) + " --seed 4 --sensors-out " +
                          (dir / "data.csv").string() + " --out " + (dir / "truth.csv").string() +
                          " > /dev/null 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  const std::string estimate = kCli + " estimate " + kFourbar + " --measurements " +
                               (dir / "data.csv").string() + " " + args + " --out " +
                               (dir / "estimated.csv").string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(estimate.c_str()), 0) << estimate;
}

std::vector<std::string> state_names(mhs_simulation* sim, mhs_estimator* est) {
  uint32_t n = 0, sensors = 0;
  EXPECT_EQ(mhs_estimator_size(sim, est, &n, &sensors), MHS_OK) << mhs_message(sim);
  std::vector<std::string> names;
  for (uint32_t k = 0; k < n; ++k) {
    const char* name = nullptr;
    const char* unit = nullptr;
    EXPECT_EQ(mhs_estimator_name(sim, est, MHS_ESTIMATOR_STATE, k, &name, &unit), MHS_OK);
    names.emplace_back(name);
  }
  return names;
}

// Each data row given to update() at its time; after each, the state, its
// standard deviations and the NIS against the command's row of that step
// (which it writes with ten digits).
void expect_the_commands_estimates(const fs::path& dir, const mhs_estimator_options& options) {
  const Table data = read_table(dir / "data.csv");
  const Table command = read_table(dir / "estimated.csv");
  ASSERT_EQ(command.rows.size(), data.rows.size());
  Sim sim = open_fourbar();
  mhs_estimator* raw = nullptr;
  ASSERT_EQ(mhs_estimator_new(sim.get(), &options, &raw), MHS_OK) << mhs_message(sim.get());
  Est est(raw);
  const std::vector<std::string> names = state_names(sim.get(), est.get());
  const size_t n = names.size();
  uint32_t sensors = 0;
  ASSERT_EQ(mhs_estimator_size(sim.get(), est.get(), nullptr, &sensors), MHS_OK);
  ASSERT_EQ(sensors, data.names.size() - 1);  // the model's sensors, the data's columns
  std::vector<double> x(n), P(n * n);
  size_t compared = 0;
  for (size_t r = 0; r < data.rows.size(); ++r) {
    const std::vector<double> readings(data.rows[r].begin() + 1, data.rows[r].end());
    ASSERT_EQ(mhs_estimator_update(sim.get(), est.get(), data.rows[r][0], readings.data(),
                                   readings.size()),
              MHS_OK)
        << mhs_message(sim.get());
    ASSERT_EQ(mhs_estimator_state(sim.get(), est.get(), x.data(), P.data(), n), MHS_OK);
    const std::vector<double>& row = command.rows[r];
    ASSERT_NEAR(row[0], data.rows[r][0], 1e-12);
    for (size_t i = 0; i < n; ++i) {
      const size_t value = command.column(names[i]), sd = command.column(names[i] + "_sd");
      ASSERT_LT(sd, command.names.size()) << names[i];
      const double s = std::sqrt(P[i * n + i]);
      EXPECT_NEAR(s, row[sd], 1e-9 * std::abs(row[sd]) + 1e-300) << names[i] << " at row " << r;
      if (value < command.names.size()) {
        EXPECT_NEAR(x[i], row[value], 1e-9 * std::abs(row[value]) + 1e-15)
            << names[i] << " at row " << r;
        ++compared;
      }
    }
    double nis = 0.0;
    ASSERT_EQ(mhs_estimator_innovations(sim.get(), est.get(), nullptr, nullptr, 0, &nis), MHS_OK);
    EXPECT_NEAR(nis, row[command.column("nis")], 1e-8 * std::abs(nis)) << "row " << r;
    // Any value of the run is the estimate: mhs_get reads it.
    uint32_t p2 = 0;
    ASSERT_EQ(mhs_find(sim.get(), "p2", &p2), MHS_OK);
    double got = 0.0;
    ASSERT_EQ(mhs_get(sim.get(), &p2, 1, &got), MHS_OK);
    EXPECT_NEAR(got, row[command.column("p2")], 1e-9 * std::abs(got)) << "row " << r;
  }
  EXPECT_GT(compared, data.rows.size());
}

TEST(EmbeddingEstimator, UpdatesWithTheDataGiveTheEstimateCommandsEstimates) {
  const fs::path dir = scratch("as-the-command");
  machine_and_command(dir, 0.3, "");
  mhs_estimator_options options{};
  options.struct_size = sizeof options;
  expect_the_commands_estimates(dir, options);
}

TEST(EmbeddingEstimator, AParameterBesideTheStateAndNoiseByNameAreTheCommandsToo) {
  const fs::path dir = scratch("parameters");
  machine_and_command(dir, 0.3,
                      "--filter ukf --estimate-params bodies/body3/mass --initial-sd "
                      "bodies/body3/mass=5 --plant-noise p1=2e4 --initial-sd z3_dot=0.01");
  const char* params[] = {"bodies/body3/mass"};
  const char* names[] = {"bodies/body3/mass", "p1", "z3_dot"};
  const double plant[] = {NAN, 2e4, NAN};
  const double initial[] = {5.0, NAN, 0.01};
  mhs_estimator_options options{};
  options.struct_size = sizeof options;
  options.filter = "ukf";
  options.params = params;
  options.param_count = 1;
  options.noise_names = names;
  options.plant_sd = plant;
  options.initial_sd = initial;
  options.noise_count = 3;
  expect_the_commands_estimates(dir, options);
}

// The run stepped or restored by another call than the estimator's is not
// the one its covariance describes: refused, naming the calls, until the
// run is back where the estimator left it.
TEST(EmbeddingEstimator, ARunMovedOutsideTheEstimatorIsRefusedUntilItIsBackWhereItWasLeft) {
  Sim sim = open_fourbar();
  mhs_simulation* s = sim.get();
  mhs_estimator* raw = nullptr;
  ASSERT_EQ(mhs_estimator_new(s, nullptr, &raw), MHS_OK) << mhs_message(s);
  const Est est(raw);
  const double readings[] = {NAN, NAN, NAN, NAN};
  ASSERT_EQ(mhs_estimator_update(s, est.get(), 0.01, readings, 4), MHS_OK) << mhs_message(s);
  mhs_snapshot* snap = nullptr;
  ASSERT_EQ(mhs_snapshot_new(s, &snap), MHS_OK);
  ASSERT_EQ(mhs_save(s, snap), MHS_OK) << mhs_message(s);
  ASSERT_LE(mhs_step(s), MHS_WARNING) << mhs_message(s);
  std::vector<double> x(6);
  for (const bool update : {true, false}) {
    EXPECT_EQ(update ? mhs_estimator_update(s, est.get(), 0.02, readings, 4)
                     : mhs_estimator_state(s, est.get(), x.data(), nullptr, 6),
              MHS_ERROR);
    EXPECT_NE(std::string(mhs_message(s)).find("the run was moved since the estimator's last call"),
              std::string::npos)
        << mhs_message(s);
  }
  ASSERT_EQ(mhs_restore(s, snap), MHS_OK) << mhs_message(s);
  mhs_snapshot_free(snap);
  EXPECT_EQ(mhs_estimator_state(s, est.get(), x.data(), nullptr, 6), MHS_OK) << mhs_message(s);
  EXPECT_EQ(mhs_estimator_update(s, est.get(), 0.02, readings, 4), MHS_OK) << mhs_message(s);
}

TEST(EmbeddingEstimator, BadCallsAreRefusedNamingWhatAndAStoppedFilterTakesNoMore) {
  Sim sim = open_fourbar();
  mhs_simulation* s = sim.get();
  mhs_estimator* raw = nullptr;
  const auto refused = [&](const mhs_estimator_options& o, const std::string& expected) {
    mhs_estimator* e = nullptr;
    EXPECT_EQ(mhs_estimator_new(s, &o, &e), MHS_ERROR) << expected;
    EXPECT_EQ(e, nullptr);
    EXPECT_NE(std::string(mhs_message(s)).find(expected), std::string::npos) << mhs_message(s);
  };
  mhs_estimator_options o{};
  o.struct_size = sizeof o;
  o.filter = "pf";
  refused(o, "filter 'pf': expected ekf or ukf");
  o.filter = nullptr;
  const char* nobody[] = {"bodies/nobody/mass"};
  o.params = nobody;
  o.param_count = 1;
  refused(o, "bodies/nobody/mass");
  o.params = nullptr;
  refused(o, "params is NULL with a param_count of 1");
  o.param_count = 0;
  const char* z9[] = {"z9"};
  const double minus[] = {-1.0};
  o.noise_names = z9;
  o.noise_count = 1;
  refused(o, "'z9' is not a state or parameter of the filter (z3, z3_dot, p1");
  const char* p2[] = {"p2"};
  o.noise_names = p2;
  o.plant_sd = minus;
  refused(o, "plant_sd[0] (p2) = -1: expected a standard deviation of 0 or more");
  o.noise_count = 0;
  o.struct_size = 8;
  refused(o, "options->struct_size is 8");
  o.struct_size = sizeof o;
  EXPECT_EQ(mhs_estimator_new(s, &o, nullptr), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("out is NULL"), std::string::npos);

  // A model without sensors.
  mhs_simulation* bare = nullptr;
  const std::string qr = std::string(mh::test::paths::source_dir) + "/models/quickreturn.yaml";
  ASSERT_LE(mhs_open_file(qr.c_str(), nullptr, 0, &bare), MHS_WARNING) << mhs_message(bare);
  Sim bare_sim(bare);
  EXPECT_EQ(mhs_estimator_new(bare, nullptr, &raw), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(bare)).find("has no sensors: add a sensors: list"),
            std::string::npos)
      << mhs_message(bare);

  ASSERT_EQ(mhs_estimator_new(s, nullptr, &raw), MHS_OK) << mhs_message(s);
  Est est(raw);
  // Used with another run.
  EXPECT_EQ(mhs_estimator_size(bare, est.get(), nullptr, nullptr), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(bare)).find("made on another run"), std::string::npos);
  const double four[] = {0.0, NAN, NAN, NAN};
  const double three[] = {0.0, NAN, NAN};
  EXPECT_EQ(mhs_estimator_update(s, est.get(), 0.0, three, 3), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("3 readings for the filter's 4 sensors"),
            std::string::npos);
  const double inf[] = {HUGE_VAL, NAN, NAN, NAN};
  EXPECT_EQ(mhs_estimator_update(s, est.get(), 0.0, inf, 4), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("sensor 'z1': reading inf"), std::string::npos)
      << mhs_message(s);
  ASSERT_EQ(mhs_estimator_update(s, est.get(), 0.01, four, 4), MHS_OK) << mhs_message(s);
  EXPECT_EQ(mhs_estimator_update(s, est.get(), 0.005, four, 4), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("t = 0.005 s falls before the run's step at 0.01 s"),
            std::string::npos)
      << mhs_message(s);
  std::vector<double> x(5);
  EXPECT_EQ(mhs_estimator_state(s, est.get(), x.data(), nullptr, 5), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("n = 5, the filter has 6 states"), std::string::npos);
  EXPECT_EQ(mhs_estimator_name(s, est.get(), MHS_ESTIMATOR_SENSOR, 4, nullptr, nullptr), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("sensor 4 is not below 4"), std::string::npos);

  // Readings no state explains (the crank at +2 and -2 mrad, step by step,
  // with 0.1 mrad of noise): the filter diverges, says so naming the
  // sensor, and takes no more.
  mhs_status st = MHS_OK;
  double t = 0.01;
  for (int k = 0; k < 400 && st == MHS_OK; ++k) {
    t += 0.001;
    const double wild[] = {k % 2 == 0 ? 2e-3 : -2e-3, NAN, NAN, NAN};
    st = mhs_estimator_update(s, est.get(), t, wild, 4);
  }
  ASSERT_EQ(st, MHS_ERROR) << "the filter took 400 wild readings";
  const std::string why = mhs_message(s);
  EXPECT_NE(why.find("the filter diverges"), std::string::npos) << why;
  EXPECT_NE(why.find("z1"), std::string::npos) << why;
  EXPECT_EQ(mhs_estimator_update(s, est.get(), t + 0.001, four, 4), MHS_ERROR);
  EXPECT_NE(std::string(mhs_message(s)).find("the filter stopped ("), std::string::npos)
      << mhs_message(s);
}

}  // namespace
