// What a model's sensors (its sensors:) read along a run: each a result
// column, sampled at its rate, late by its delay, offset by its bias, with
// white Gaussian noise of its standard deviation drawn from a seeded
// generator of its own (so that one sensor's readings do not change when
// another is added). `run --sensors-out` writes them; they are the data
// identification and estimation read.
#pragma once

#include <cstdint>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {

class SensorSampler {
 public:
  // Resolves each sensor's column among every column `sim` writes and its
  // rate and delay into whole numbers of steps. Throws InputError at the
  // sensor's line: an unknown column (naming those there are), a sampling
  // period 1/rate or a delay that is not a whole number of steps dt.
  SensorSampler(const Simulation& sim, const std::vector<SensorSpec>& sensors, std::uint64_t seed);
  // The columns alone: what every run of the model checks, its rates and
  // delays being the business of the runs that read the sensors (a run at
  // another dt need not fit a 1 kHz encoder).
  static void check_columns(const Simulation& sim, const std::vector<SensorSpec>& sensors);

  // The accepted state of step k = sim.step_index(): call it at the start and
  // after every step, in order. True when a sensor has a sample at this
  // step; values() then holds the readings, NaN for the sensors that have
  // none (off their rate, or not yet past their delay).
  bool sample(const Simulation& sim);
  const std::vector<double>& values() const { return readings_; }

  // "t,NAME,..." and a row of the last sample: an empty field for a sensor
  // without a reading.
  void header(std::ostream& out) const;
  void row(std::ostream& out, double t) const;

 private:
  struct Channel {
    std::string name;
    std::size_t column = 0;  // in the full layout
    long every = 1;          // steps between samples
    long delay = 0;          // steps
    double noise = 0.0, bias = 0.0;
    std::vector<double> history;  // the last delay + 1 true values, a ring
    std::mt19937_64 rng;
    std::normal_distribution<double> normal{0.0, 1.0};  // its own: it keeps a drawn pair
  };
  CsvLayout layout_;               // every column the run writes
  std::vector<double> truth_;      // one row of it
  std::vector<Channel> channels_;  // in file order
  std::vector<double> readings_;
};

}  // namespace mh
