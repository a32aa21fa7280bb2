// The extended Kalman filter (core/src/estimation/extended_kalman_filter.cpp)
// by the three-simulation method of Jaiswal et al. 2022: a truth, the
// hydraulic four-bar with errors in its force model; its sensors' readings
// with seeded white noise; the filter on the nominal model. Judged against
// the nominal model run open loop from the same start, and by its own
// covariance against the errors it actually makes.
#include "monohydra/core/extended_kalman_filter.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/state_vector.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

ModelFile fourbar(double t_end) {
  ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  file.solver.t_end = t_end;
  return file;
}

void set_option(ModelFile& file, const std::string& subsystem, const std::string& key,
                double value) {
  for (SubsystemSpec& s : file.subsystems)
    if (s.name == subsystem) s.options.at(key).number = value;
}

// The machine: the load's mass +10 %, the cylinder's friction x2
// (efficiency 0.88 -> 0.76), the hoses' bulk modulus -20 %.
ModelFile machine_of(ModelFile file) {
  file.model.bodies[2].mass *= 1.10;
  file.model.bodies[2].inertia_B *= 1.10;
  set_option(file, "cylinder", "efficiency", 0.76);
  for (const char* v : {"V1", "V2", "V3"}) set_option(file, v, "bulk_modulus", 0.8 * 550e6);
  return file;
}

// The plant noise the four-bar's filter is tuned with: the error a force
// model 10-20 % off puts on the rates over a second (docs/estimation.md).
FilterNoise tuned_noise(const std::vector<LinearVariable>& states) {
  const auto n = static_cast<Eigen::Index>(states.size());
  FilterNoise noise{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::string& unit = states[static_cast<size_t>(i)].unit;
    noise.plant[i] = unit == "rad/s" ? 3e-2 : unit == "Pa" ? 1e4 : unit == "V" ? 1e-3 : 0.0;
    noise.initial[i] = unit == "rad/s" ? 1e-3 : unit == "Pa" ? 1e5 : 1e-3;
  }
  return noise;
}

struct Outcome {
  std::vector<std::string> names;
  Eigen::VectorXd filter_rms, open_rms;
  double nees_inside = 0.0;  // the fraction of steps inside the two-sided 95 % band
  double nees_above = 0.0;   // ... above it: the filter overconfident
};

// The truth's reading of each sensor at its rate (steps between samples).
double reading(const Simulation& truth, const FilterSensor& s) {
  const std::vector<std::string>& states = truth.state_names();
  for (size_t i = 0; i < states.size(); ++i)
    if (states[i] == s.measures) return truth.states()[static_cast<Eigen::Index>(i)];
  const std::vector<std::string>& outputs = truth.output_names();
  for (size_t i = 0; i < outputs.size(); ++i)
    if (outputs[i] == s.measures) return truth.outputs()[static_cast<Eigen::Index>(i)];
  if (s.measures == "z1") return truth.z()[0];
  throw std::invalid_argument("no column " + s.measures);
}

Outcome three_simulations(const std::vector<FilterSensor>& sensors, const std::vector<long>& every,
                          double t_end, unsigned seed) {
  const ModelFile nominal = fourbar(t_end);
  const ModelFile machine = machine_of(nominal);
  Simulation truth(machine, test::build_plugins());
  Simulation open(nominal, test::build_plugins());
  Simulation estimated(nominal, test::build_plugins());
  truth.start();
  open.start();
  estimated.start();
  Outcome out;
  const std::vector<LinearVariable> states = state_variables(estimated);
  for (const LinearVariable& v : states) out.names.push_back(v.name);
  ExtendedKalmanFilter filter(estimated, sensors, tuned_noise(states));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  const auto n = static_cast<Eigen::Index>(states.size());
  out.filter_rms = out.open_rms = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd y(static_cast<Eigen::Index>(sensors.size()));
  const long steps = std::lround(t_end / nominal.solver.dt);
  long inside = 0, above = 0;
  // The two-sided 95 % band of a chi-square of n = 6 degrees of freedom.
  EXPECT_EQ(n, 6);
  const double low = 1.2373, high = 14.4494;
  for (long k = 0; k <= steps; ++k) {
    if (k > 0) {
      truth.step();
      open.step();
      filter.predict();
    }
    for (size_t i = 0; i < sensors.size(); ++i)
      y[static_cast<Eigen::Index>(i)] =
          k % every[i] == 0 ? reading(truth, sensors[i]) + sensors[i].noise * normal(rng) : NAN;
    filter.update(y);
    const Eigen::VectorXd truth_x = state_values(truth);
    const Eigen::VectorXd e = state_values(estimated) - truth_x;
    out.filter_rms += e.cwiseAbs2();
    out.open_rms += (state_values(open) - truth_x).cwiseAbs2();
    const double nees = e.dot(filter.covariance().ldlt().solve(e));
    inside += nees > low && nees < high ? 1 : 0;
    above += nees >= high ? 1 : 0;
  }
  const auto count = static_cast<double>(steps + 1);
  out.filter_rms = (out.filter_rms / count).cwiseSqrt();
  out.open_rms = (out.open_rms / count).cwiseSqrt();
  out.nees_inside = static_cast<double>(inside) / count;
  out.nees_above = static_cast<double>(above) / count;
  if (std::getenv("MH_EKF_PRINT") != nullptr) {
    for (Eigen::Index i = 0; i < n; ++i)
      std::printf("%s %.3f  ", out.names[static_cast<size_t>(i)].c_str(),
                  out.filter_rms[i] / out.open_rms[i]);
    std::printf("inside %.3f above %.3f\n", out.nees_inside, out.nees_above);
  }
  return out;
}

const double kPressureNoise = 0.005 * 7.6e6;  // 0.5 % of the supply pressure

// Each state the open-loop model gets wrong, against it: coordinates and
// pressures at most a tenth of the open loop's RMS error (the issue's
// bound); the rate at most a quarter: the encoder's noise sets its floor,
// about 2e-3 rad/s, where the open loop is exact (at rest, before the
// valve opens) and 1e-2 rad/s over the run.
void expect_tracks(const Outcome& o) {
  for (size_t i = 0; i < o.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (o.names[i] == "U") continue;  // the spool: the model's is exact
    const double bound =
        o.names[i].size() > 4 && o.names[i].substr(o.names[i].size() - 4) == "_dot" ? 0.25 : 0.1;
    EXPECT_LT(o.filter_rms[k], bound * o.open_rms[k])
        << o.names[i] << ": filter " << o.filter_rms[k] << ", open loop " << o.open_rms[k];
  }
  // Consistent: the error normalised by the filter's own covariance is
  // above the chi-square band's upper end (the filter sure of a state it
  // has wrong) in under 10 % of the steps (2.4 to 5.7 % measured).
  EXPECT_LT(o.nees_above, 0.1);
}

TEST(ExtendedKalmanFilter,
     EncoderAndBothChamberPressuresTrackTheMachineTenTimesCloserThanTheModel) {
  const Outcome o = three_simulations({{"encoder", "z1", 1e-4, 0.0},
                                       {"pA", "p2", kPressureNoise, 0.0},
                                       {"pB", "p3", kPressureNoise, 0.0}},
                                      {1, 1, 1}, 4.0, 1);
  expect_tracks(o);
  EXPECT_GT(o.nees_inside, 0.8);
}

// The crank's encoder alone sees the mechanism, and the chambers'
// pressures only through their difference, which moves it: their common
// level stays about a third of the open loop's error.
TEST(ExtendedKalmanFilter, AnEncoderAloneTracksTheMechanismButLessThePressures) {
  const Outcome o = three_simulations({{"encoder", "z1", 1e-4, 0.0}}, {1}, 4.0, 4);
  EXPECT_LT(o.filter_rms[0], 0.1 * o.open_rms[0]);
  for (Eigen::Index i = 2; i < 5; ++i)
    EXPECT_LT(o.filter_rms[i], 0.5 * o.open_rms[i]) << o.names[static_cast<size_t>(i)];
  EXPECT_LT(o.nees_above, 0.1);
}

TEST(ExtendedKalmanFilter, AStrokeSensorAloneTracksTheMachineTenTimesCloserThanTheModel) {
  expect_tracks(three_simulations({{"stroke", "s", 1e-5, 0.0}}, {1}, 4.0, 2));
}

TEST(ExtendedKalmanFilter, AnEncoderAt100HzWithPressuresAt1kHzTracksTheMachine) {
  expect_tracks(three_simulations({{"encoder", "z1", 1e-4, 0.0},
                                   {"pA", "p2", kPressureNoise, 0.0},
                                   {"pB", "p3", kPressureNoise, 0.0}},
                                  {10, 1, 1}, 4.0, 3));
}

// The error of a sensor whose noise is understated, or of one that reads
// far from anything the model can do: a message naming the sensor and the
// reason, not numbers.
std::string filter_error(double offset, double stated_noise, double noise) {
  const ModelFile file = fourbar(2.0);
  Simulation sim(file, test::build_plugins());
  sim.start();
  ExtendedKalmanFilter filter(sim, {{"pA", "p2", stated_noise, 0.0}},
                              tuned_noise(state_variables(sim)));
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  Eigen::VectorXd y(1);
  try {
    for (int k = 0; k < 2000; ++k) {
      y[0] = sim.states()[1] + offset + noise * normal(rng);
      filter.update(y);
      filter.predict();
    }
  } catch (const SimulationError& err) {
    return err.what();
  }
  return "";
}

TEST(ExtendedKalmanFilter, ASensorWhoseNoiseIsUnderstatedIsReportedAsDivergence) {
  // Its readings 38 kPa about the truth, the filter told 1 kPa.
  const std::string what = filter_error(0.0, 1e3, kPressureNoise);
  EXPECT_NE(what.find("diverges"), std::string::npos) << what;
  EXPECT_NE(what.find("pA"), std::string::npos) << what;
}

TEST(ExtendedKalmanFilter, AReadingNoStateOfTheModelExplainsStopsWithTheSensorAndTheReason) {
  // 2 MPa off, believed to 100 Pa: the correction drives the piston out of
  // its cylinder.
  const std::string what = filter_error(2e6, 100.0, 0.0);
  EXPECT_NE(what.find("cannot be applied"), std::string::npos) << what;
  EXPECT_NE(what.find("pA"), std::string::npos) << what;
  EXPECT_NE(what.find("cylinder"), std::string::npos) << what;
}

TEST(ExtendedKalmanFilter, RefusesASensorOfAColumnTheRunDoesNotWriteOrWithoutNoise) {
  const ModelFile file = fourbar(1.0);
  Simulation sim(file, test::build_plugins());
  sim.start();
  const FilterNoise noise = tuned_noise(state_variables(sim));
  EXPECT_THROW(ExtendedKalmanFilter(sim, {{"x", "p9", 1.0, 0.0}}, noise), std::invalid_argument);
  EXPECT_THROW(ExtendedKalmanFilter(sim, {{"x", "p2", 0.0, 0.0}}, noise), std::invalid_argument);
  FilterNoise negative = noise;
  negative.plant[0] = -1.0;
  EXPECT_THROW(ExtendedKalmanFilter(sim, {{"x", "p2", 1.0, 0.0}}, negative), std::invalid_argument);
  ExtendedKalmanFilter filter(sim, {{"x", "p2", 1.0, 0.0}}, noise);
  EXPECT_THROW(filter.update(Eigen::VectorXd::Constant(1, HUGE_VAL)), std::invalid_argument);
  EXPECT_THROW(filter.update(Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace mh
