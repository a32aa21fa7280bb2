// A model as an FMU carries it: resources/model.yaml (the model with its
// formulation and integrator chosen and its plugins beside it), and the
// table of the FMU's variables that both the modelDescription.xml and the
// binary derive from that file alone, so the two cannot disagree: value
// reference 0 the independent time, then every column `monohydra run`
// writes, the model's inputs, and its numeric options as parameters.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/simulation.h"

namespace mh::fmu {

enum class Causality { independent, output, input, parameter };

struct FmuVariable {
  std::uint32_t value_reference = 0;
  Causality causality = Causality::output;
  std::string name;             // the CSV column, the input's name, "subsystems.valve.area"
  std::string unit;             // SI, "" when none is declared
  std::string description;      // what it is, for the modelDescription
  std::string path;             // a parameter's path in the model ("subsystems/valve/area")
  double start = 0.0;           // inputs and parameters
  bool tunable = false;         // a parameter set between steps too (a body's mass)
  double min = 1.0, max = 0.0;  // min > max: no range
  std::uint32_t index = 0;      // a row column (output) or an mhs variable (input)
};

// The files in resources/: the model, and what `monohydra fmu` chose over
// it as the command line's flags do (settings: a list of {path, value}, as
// the embedding API's mhs_setting: formulation, integrator).
inline constexpr const char* kModelFile = "model.yaml";
inline constexpr const char* kSettingsFile = "monohydra-fmu.yaml";

struct PackedModel {
  std::string model_path;  // resources/model.yaml
  std::string model_text;
  std::string settings_text;  // "" when there is no settings file
  std::vector<std::pair<std::string, std::string>> settings;
  std::string token;  // instantiation_token of both texts
};

// Reads both files of `resources_dir` (with or without a trailing '/').
// Throws std::runtime_error naming a file that cannot be read or is not
// what it should be.
PackedModel read_packed_model(const std::string& resources_dir);

// The model's settings as the embedding API takes them (pointers into `packed`).
std::vector<mhs_setting> api_settings(const PackedModel& packed);

// The instantiation token of a model's text: a digest of it (two FNV-1a
// hashes) written as a GUID, so an FMU whose resources were changed is
// refused at instantiation rather than run with the wrong variables.
std::string instantiation_token(const std::string& model_text);

// The numeric options of a model's text, as parameters: each subsystem's
// and body's scalar numbers and the formulation's, with their paths in the
// model (parameter_path.hpp) and their values as written.
std::vector<FmuVariable> numeric_options(const std::string& model_text);

// The whole variable table of a started run of the model (`sim`) whose text is `model_text`. Throws
// std::runtime_error when two variables would share a name.
std::vector<FmuVariable> variable_table(mhs_simulation* sim, const std::string& model_text);

// The file's text; throws std::runtime_error naming the file when it cannot be read.
std::string read_text(const std::string& path);

}  // namespace mh::fmu
