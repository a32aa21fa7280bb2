// What every state filter shares (core/src/estimation/state_filter.cpp):
// its refusals, and a filter that stops with the sensor and the reason
// rather than writing numbers (the extended filter drives them).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "three_simulations.hpp"

namespace mh {
namespace {

using test::build_plugins;
using test::fourbar;
using test::kPressureNoise;
using test::tuned_noise;

// The error of a sensor whose noise is understated, or of one that reads
// far from anything the model can do: a message naming the sensor and the
// reason, not numbers.
std::string filter_error(double offset, double stated_noise, double noise) {
  const ModelFile file = fourbar(2.0);
  Simulation sim(file, build_plugins());
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

TEST(StateFilter, ASensorWhoseNoiseIsUnderstatedIsReportedAsDivergence) {
  // Its readings 38 kPa about the truth, the filter told 1 kPa.
  const std::string what = filter_error(0.0, 1e3, kPressureNoise);
  EXPECT_NE(what.find("diverges"), std::string::npos) << what;
  EXPECT_NE(what.find("pA"), std::string::npos) << what;
}

TEST(StateFilter, AReadingNoStateOfTheModelExplainsStopsWithTheSensorAndTheReason) {
  // 2 MPa off, believed to 100 Pa: the correction drives the piston out of
  // its cylinder.
  const std::string what = filter_error(2e6, 100.0, 0.0);
  EXPECT_NE(what.find("cannot be applied"), std::string::npos) << what;
  EXPECT_NE(what.find("pA"), std::string::npos) << what;
  EXPECT_NE(what.find("cylinder"), std::string::npos) << what;
}

TEST(StateFilter, RefusesASensorOfAColumnTheRunDoesNotWriteOrWithoutNoise) {
  const ModelFile file = fourbar(1.0);
  Simulation sim(file, build_plugins());
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
