// A filter's defaults (core/src/estimation/filter_defaults.cpp): each
// state's noise by its unit, a parameter's by its value, and a model file's
// sensor taken or refused with its name.
#include "monohydra/core/filter_defaults.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace mh {
namespace {

TEST(FilterDefaults, PositionsHaveNoPlantNoiseRatesAndPressuresTheFourBarsTuning) {
  const std::vector<LinearVariable> states = {
      {"z3", "rad"}, {"s", "m"}, {"z3_dot", "rad/s"}, {"p1", "Pa"}, {"U", "V"}};
  ParameterDirection mass, zero;
  mass.value = -250.0;  // its size counts
  zero.value = 0.0;
  const FilterNoise n = default_filter_noise(states, {mass, zero});
  ASSERT_EQ(n.plant.size(), 5);
  EXPECT_EQ(n.plant[0], 0.0);
  EXPECT_EQ(n.plant[1], 0.0);
  EXPECT_EQ(n.plant[2], 3e-2);
  EXPECT_EQ(n.plant[3], 1e4);
  EXPECT_EQ(n.plant[4], 1e-3);
  EXPECT_EQ(n.initial[0], 1e-3);
  EXPECT_EQ(n.initial[3], 1e5);
  EXPECT_EQ(n.initial[4], 1e-3);
  ASSERT_EQ(n.parameter_plant.size(), 2);
  EXPECT_EQ(n.parameter_plant[0], 0.0);
  EXPECT_DOUBLE_EQ(n.parameter_initial[0], 50.0);
  EXPECT_DOUBLE_EQ(n.parameter_initial[1], 0.2);
}

TEST(FilterDefaults, ASensorIsTakenWithItsNoiseBiasAndDelayOrRefusedNamingIt) {
  SensorSpec s;
  s.name = "crank";
  s.measures = "z1";
  s.noise = 1e-4;
  s.bias = 2e-4;
  const FilterSensor f = filter_sensor(s, "m.yaml");
  EXPECT_EQ(f.name, "crank");
  EXPECT_EQ(f.measures, "z1");
  EXPECT_EQ(f.noise, 1e-4);
  EXPECT_EQ(f.bias, 2e-4);
  const auto refusal = [](const SensorSpec& spec) {
    try {
      filter_sensor(spec, "m.yaml");
    } catch (const std::invalid_argument& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  SensorSpec delayed = s;
  delayed.delay = 0.01;
  EXPECT_EQ(filter_sensor(delayed, "m.yaml").delay, 0.01);
  SensorSpec silent = s;
  silent.noise = 0.0;
  EXPECT_EQ(refusal(silent),
            "sensor 'crank' (m.yaml): a filter needs its noise (a standard deviation above 0)");
}

}  // namespace
}  // namespace mh
