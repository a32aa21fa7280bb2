// The unscented Kalman filter (core/src/estimation/unscented_kalman_filter.cpp)
// by the three-simulation test on the four-bar (three_simulations.hpp),
// against the bounds the extended filter meets.
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

// The unscented filter, no derivative of the step, on the same machine and
// sensors as the extended one: the same bounds.
TEST(UnscentedKalmanFilter, EncoderAndBothChamberPressuresTrackTheMachineAsTheExtendedFilterDoes) {
  const Outcome o = three_simulations({{"encoder", "z1", 1e-4, 0.0},
                                       {"pA", "p2", kPressureNoise, 0.0},
                                       {"pB", "p3", kPressureNoise, 0.0}},
                                      {1, 1, 1}, 4.0, 1, true);
  expect_tracks(o);
}

}  // namespace
}  // namespace mh
