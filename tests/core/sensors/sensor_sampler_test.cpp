// What a model's sensors read (core/src/sensors/sensor_sampler.cpp): the
// true column at the sensor's rate, late by its delay and offset by its bias;
// white noise of its standard deviation (mean and spread measured), seeded;
// bad columns, rates and delays refused at the sensor's line.
#include "monohydra/core/sensor_sampler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "monohydra/core/input_error.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

ModelFile pendulum_with(const std::string& sensors) {
  std::ifstream in(test::source_path("models/double-pendulum.yaml"));
  std::stringstream text;
  text << in.rdbuf() << "sensors:\n" << sensors;
  return parse_model_text(text.str(), "pendulum.yaml", test::source_path("models"));
}

// Steps a run to `steps`, keeping the true z1 of every step and each sample
// the sampler took (step -> readings).
struct Record {
  std::vector<double> z1, z2;
  std::map<long, std::vector<double>> samples;
};

Record record(const ModelFile& file, long steps, std::uint64_t seed) {
  Simulation sim(file, test::build_plugins());
  SensorSampler sampler(sim, file.sensors, seed);
  sim.start();
  Record r;
  for (long k = 0;; ++k) {
    r.z1.push_back(sim.z()[0]);
    r.z2.push_back(sim.z()[1]);
    if (sampler.sample(sim)) r.samples[k] = sampler.values();
    if (k == steps) break;
    sim.step();
  }
  return r;
}

TEST(SensorSampler, ANoiselessSensorReadsItsColumnAtItsRateLateByItsDelayAndOffsetByItsBias) {
  const ModelFile file = pendulum_with(
      "  - {name: every, measures: z1}\n"
      "  - {name: slow, measures: z2, rate: 100, delay: 0.003, bias: 0.25}\n");
  const Record r = record(file, 100, 1);
  ASSERT_EQ(r.samples.size(), 101u);  // `every` has one at every step
  for (const auto& [k, v] : r.samples) {
    EXPECT_EQ(v[0], r.z1[static_cast<size_t>(k)]);
    if (k % 10 == 0 && k >= 3) {
      EXPECT_EQ(v[1], r.z2[static_cast<size_t>(k - 3)] + 0.25) << "step " << k;
    } else {
      EXPECT_TRUE(std::isnan(v[1])) << "step " << k;
    }
  }
}

TEST(SensorSampler, NoiseHasZeroMeanAndItsStandardDeviationAndIsTheSameForTheSameSeed) {
  const ModelFile file = pendulum_with("  - {name: crank, measures: z1, noise: 1e-3}\n");
  const long steps = 20000;
  const Record a = record(file, steps, 7);
  double sum = 0.0, sum2 = 0.0;
  for (const auto& [k, v] : a.samples) {
    const double e = v[0] - a.z1[static_cast<size_t>(k)];
    sum += e;
    sum2 += e * e;
  }
  const double n = static_cast<double>(a.samples.size());
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4.0 * 1e-3 / std::sqrt(n));  // 4 standard errors
  EXPECT_NEAR(sd, 1e-3, 4.0 * 1e-3 / std::sqrt(2.0 * n));
  EXPECT_EQ(record(file, 50, 7).samples, record(file, 50, 7).samples);
  EXPECT_NE(record(file, 50, 7).samples, record(file, 50, 8).samples);
}

TEST(SensorSampler, AddingASensorLeavesAnotherSensorsNoiseAlone) {
  const Record one = record(pendulum_with("  - {name: a, measures: z1, noise: 1e-3}\n"), 50, 3);
  const Record two = record(pendulum_with("  - {name: a, measures: z1, noise: 1e-3}\n"
                                          "  - {name: b, measures: z2, noise: 1e-3}\n"),
                            50, 3);
  for (const auto& [k, v] : one.samples) EXPECT_EQ(two.samples.at(k)[0], v[0]);
}

TEST(SensorSampler, AnUnknownColumnARateOffTheStepsAndADelayOffTheStepsAreRefusedAtTheirLine) {
  const auto refusal = [](const std::string& sensors) {
    const ModelFile file = pendulum_with(sensors);
    const Simulation sim(file, test::build_plugins());
    try {
      SensorSampler(sim, file.sensors, 1);
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  const std::string column = refusal("  - {name: p, measures: p9}\n");
  EXPECT_NE(column.find("pendulum.yaml:"), std::string::npos) << column;
  EXPECT_NE(column.find("sensors[0].measures: unknown column 'p9' (this run writes: t, z1, z2"),
            std::string::npos)
      << column;
  EXPECT_NE(refusal("  - {name: c, measures: z1, rate: 300}\n")
                .find("sensors[0].rate: expected a rate whose period 1/rate is a whole number of "
                      "steps dt = 0.001 s, got 300 Hz"),
            std::string::npos);
  EXPECT_NE(refusal("  - {name: c, measures: z1, delay: 0.0015}\n")
                .find("sensors[0].delay: expected a whole number of steps"),
            std::string::npos);
}

TEST(SensorSampler, TheFileRefusesADuplicateNameANegativeNoiseAndAnUnknownKey) {
  const auto refusal = [](const std::string& sensors) {
    try {
      pendulum_with(sensors);
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("  - {name: a, measures: z1}\n  - {name: a, measures: z2}\n")
                .find("duplicate sensor name 'a'"),
            std::string::npos);
  EXPECT_NE(refusal("  - {name: a, measures: z1, noise: -1}\n")
                .find("sensors[0].noise: expected a non-negative finite number"),
            std::string::npos);
  EXPECT_NE(refusal("  - {name: a, measures: z1, sigma: 1}\n").find("sigma"), std::string::npos);
  EXPECT_NE(refusal("  - {name: a}\n").find("measures"), std::string::npos);
  EXPECT_NE(refusal("  - {name: t, measures: z1}\n").find("other than t"), std::string::npos);
}

TEST(SensorSampler, ARowHasTheTimeAndAnEmptyFieldWhereASensorTookNoSample) {
  const ModelFile file =
      pendulum_with("  - {name: a, measures: z1}\n  - {name: b, measures: z2, rate: 500}\n");
  Simulation sim(file, test::build_plugins());
  SensorSampler sampler(sim, file.sensors, 1);
  sim.start();
  sim.step();
  ASSERT_TRUE(sampler.sample(sim));
  std::ostringstream out;
  sampler.header(out);
  sampler.row(out, sim.time());
  std::ostringstream z1;
  monohydra::put_exact_number(z1, sim.z()[0]);
  EXPECT_EQ(out.str(), "t,a,b\n0.001," + z1.str() + ",\n");
}

}  // namespace
}  // namespace mh
