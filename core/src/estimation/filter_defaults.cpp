#include "monohydra/core/filter_defaults.hpp"

#include <cmath>
#include <stdexcept>

#include "monohydra/cpp/number_text.hpp"

namespace mh {

namespace {

double default_plant(const std::string& unit) {
  if (unit == "Pa") return 1e4;
  if (unit.size() > 2 && unit.substr(unit.size() - 2) == "/s") return 3e-2;
  if (unit == "rad" || unit == "m") return 0.0;
  return 1e-3;
}

double default_initial(const std::string& unit) {
  return unit == "Pa" ? 1e5 : 1e-3;
}

}  // namespace

FilterNoise default_filter_noise(const std::vector<LinearVariable>& states,
                                 const std::vector<ParameterDirection>& parameters) {
  const auto n = static_cast<Eigen::Index>(states.size());
  const auto k = static_cast<Eigen::Index>(parameters.size());
  FilterNoise noise{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(k), Eigen::VectorXd(k)};
  for (Eigen::Index i = 0; i < n; ++i) {
    noise.plant[i] = default_plant(states[static_cast<size_t>(i)].unit);
    noise.initial[i] = default_initial(states[static_cast<size_t>(i)].unit);
  }
  for (Eigen::Index j = 0; j < k; ++j) {
    const double v = parameters[static_cast<size_t>(j)].value;
    noise.parameter_plant[j] = 0.0;
    noise.parameter_initial[j] = 0.2 * (v != 0.0 ? std::abs(v) : 1.0);
  }
  return noise;
}

FilterSensor filter_sensor(const SensorSpec& spec, const std::string& model) {
  if (!(spec.noise > 0.0))
    throw std::invalid_argument("sensor '" + spec.name + "' (" + model +
                                "): a filter needs its noise (a standard deviation above 0)");
  return {spec.name, spec.measures, spec.noise, spec.bias, spec.delay};
}

}  // namespace mh
