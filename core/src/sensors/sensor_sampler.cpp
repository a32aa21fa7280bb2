#include "monohydra/core/sensor_sampler.hpp"

#include <cmath>
#include <limits>

#include "monohydra/core/input_error.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh {
namespace {

using monohydra::short_number;

// `seconds` as a whole number of steps dt, or -1 when it is not one.
long whole_steps(double seconds, double dt) {
  const double steps = seconds / dt;
  const double whole = std::round(steps);
  if (std::abs(steps - whole) > 1e-9 * std::max(whole, 1.0) || whole > 1e15) return -1;
  return static_cast<long>(whole);
}

}  // namespace

namespace {

// The column of `s` among `names`; InputError at its line when none.
std::size_t column_of(const SensorSpec& s, std::size_t index,
                      const std::vector<std::string>& names) {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == s.measures) return k;
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw InputError(s.measures_mark, "sensors[" + std::to_string(index) + "].measures",
                   "unknown column '" + s.measures + "' (this run writes: " + known + ")");
}

}  // namespace

void SensorSampler::check_columns(const Simulation& sim, const std::vector<SensorSpec>& sensors) {
  const CsvLayout layout(sim);
  for (std::size_t i = 0; i < sensors.size(); ++i) column_of(sensors[i], i, layout.names());
}

SensorSampler::SensorSampler(const Simulation& sim, const std::vector<SensorSpec>& sensors,
                             std::uint64_t seed)
    : layout_(sim) {
  const double dt = sim.settings().dt;
  const std::vector<std::string>& names = layout_.names();
  truth_.assign(names.size(), 0.0);
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    const SensorSpec& s = sensors[i];
    const std::string field = "sensors[" + std::to_string(i) + "]";
    Channel c;
    c.name = s.name;
    c.column = column_of(s, i, names);
    if (s.rate > 0.0) {
      c.every = whole_steps(1.0 / s.rate, dt);
      if (c.every < 1)
        throw InputError(s.rate_mark, field + ".rate",
                         "expected a rate whose period 1/rate is a whole number of steps dt = " +
                             short_number(dt) + " s, got " + short_number(s.rate) +
                             " Hz (a period of " + short_number(1.0 / s.rate / dt) + " steps)");
    }
    c.delay = whole_steps(s.delay, dt);
    if (c.delay < 0 || c.delay > 10000000)
      throw InputError(s.delay_mark, field + ".delay",
                       "expected a whole number of steps dt = " + short_number(dt) +
                           " s (at most 1e7), got " + short_number(s.delay) + " s");
    c.noise = s.noise;
    c.bias = s.bias;
    c.history.assign(static_cast<std::size_t>(c.delay) + 1,
                     std::numeric_limits<double>::quiet_NaN());
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(i)};
    c.rng.seed(seq);
    channels_.push_back(std::move(c));
  }
  readings_.assign(channels_.size(), std::numeric_limits<double>::quiet_NaN());
}

bool SensorSampler::sample(const Simulation& sim) {
  const long k = sim.step_index();
  layout_.values(sim, truth_.data());
  bool any = false;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    Channel& c = channels_[i];
    const auto ring = static_cast<long>(c.history.size());
    c.history[static_cast<std::size_t>(k % ring)] = truth_[c.column];
    double reading = std::numeric_limits<double>::quiet_NaN();
    if (k % c.every == 0 && k >= c.delay) {
      // The value of step k - delay: the ring's oldest entry.
      const double truth = c.history[static_cast<std::size_t>((k - c.delay) % ring)];
      if (!std::isnan(truth)) {
        reading = truth + c.bias;
        if (c.noise > 0.0) reading += c.noise * c.normal(c.rng);
        any = true;
      }
    }
    readings_[i] = reading;
  }
  return any;
}

void SensorSampler::header(std::ostream& out) const {
  out << 't';
  for (const Channel& c : channels_) out << ',' << c.name;
  out << '\n';
}

void SensorSampler::row(std::ostream& out, double t) const {
  monohydra::put_exact_number(out, t);
  for (const double v : readings_) {
    out << ',';
    if (!std::isnan(v)) monohydra::put_exact_number(out, v);
  }
  out << '\n';
}

}  // namespace mh
