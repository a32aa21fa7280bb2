// What a filter is told when its user says nothing (docs/estimation.md):
// the noise of each state by its unit, tuned on the four-bar, and a model
// file's sensor as a filter reads it. The command line (`estimate`), the
// embedding API and Python set a filter up through these, so that the same
// model and data give the same estimates from each.
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/state_filter.hpp"
#include "monohydra/core/state_vector.hpp"

namespace mh {

// Per state of X: plant noise on rates (3e-2 per sqrt(s)) and pressures
// (1e4 Pa per sqrt(s)), none on positions, 1e-3 on anything else; an
// initial error of 1e5 Pa on pressures, 1e-3 else. Per parameter: no plant
// noise (a constant) and an initial error of a fifth of its value (of 1
// where it is 0).
FilterNoise default_filter_noise(const std::vector<LinearVariable>& states,
                                 const std::vector<ParameterDirection>& parameters);

// The model's sensor `spec` as a filter takes it (its delay too: the
// filter's constructor checks it is a whole number of steps). Throws
// std::invalid_argument naming the sensor and `model`: a noise not above 0.
FilterSensor filter_sensor(const SensorSpec& spec, const std::string& model);

}  // namespace mh
