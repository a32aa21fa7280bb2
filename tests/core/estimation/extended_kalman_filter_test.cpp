// The extended Kalman filter (core/src/estimation/extended_kalman_filter.cpp)
// by the three-simulation test on the four-bar (three_simulations.hpp), in
// four sensor configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "three_simulations.hpp"

namespace mh {
namespace {

using test::expect_tracks;
using test::kPressureNoise;
using test::Outcome;
using test::three_simulations;

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

}  // namespace
}  // namespace mh
