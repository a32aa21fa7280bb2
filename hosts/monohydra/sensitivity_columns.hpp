// The result columns that carry sensitivities (Simulation::track_sensitivities),
// shared by `monohydra sensitivities` and `monohydra fit`: every coordinate,
// named state and differentiated output, in the order `run` writes them; and
// each --params path as the engine takes it, found in the text the run was
// made of (with its --set values).
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/sensitivities.hpp"
#include "monohydra/core/simulation.hpp"
#include "run_setup.hpp"

namespace mh::cli {

struct SensitivityColumn {
  enum class Kind { coordinate, state, output } kind;
  int index;
  std::string name;
};

std::vector<SensitivityColumn> sensitivity_columns(const Simulation& sim);
// Its value and its derivative with respect to parameter j, at the accepted state.
double column_value(const Simulation& sim, const SensitivityColumn& c);
double column_sensitivity(const Simulation& sim, const SensitivityColumn& c, int j);

// The directions of `paths` for a run of `request` (its model file and --set
// values) that parsed to `file`. Throws std::invalid_argument starting with
// the path it cannot take (parameter_direction.hpp).
std::vector<ParameterDirection> parameter_directions(const RunRequest& request,
                                                     const ModelFile& file,
                                                     const std::vector<std::string>& paths);

}  // namespace mh::cli
