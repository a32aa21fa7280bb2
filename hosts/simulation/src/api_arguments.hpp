// Arguments that a run's calls (simulation_api.cpp) and a batch's
// (batch_api.cpp) read alike: the settings an open takes, and a value's
// description. Each returns why it refuses ("" when it does not).
#pragma once

#include <string>
#include <vector>

#include "monohydra/simulation.h"
#include "opened_model.hpp"
#include "variable_table.hpp"

namespace mh::embed {

// The settings as pairs into request.settings.
std::string read_settings(const mhs_setting* settings, size_t count, OpenRequest& request);

// Value `index` of `table` described in `info` (its strings the table's).
std::string describe(const char* call, const std::vector<Variable>& table, uint32_t index,
                     mhs_variable_info* info);

// The shortest text that reads back as the same double (a parameter's
// value as the model file would write it).
std::string exact_text(double value);

}  // namespace mh::embed
