// What the import reads of an FMU's modelDescription.xml (FMI 3.0, 2.4): the
// version, the token, the Model Exchange capabilities and the Float64
// variables it connects (continuous states and their derivatives, inputs,
// outputs, parameters). Anything it cannot run is refused here, with the
// reason, before the binary is loaded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fmu {

struct Variable {
  std::string name;
  uint32_t vr = 0;  // valueReference
  std::string causality, variability, unit;
  double start = 0.0;
  bool has_start = false;
};

struct ModelDescription {
  std::string fmi_version, model_name, instantiation_token, model_identifier;
  bool provides_directional_derivatives = false;
  bool can_get_and_set_state = false, can_serialize_state = false;
  bool needs_completed_integrator_step = false;
  std::vector<Variable> states;       // continuous states, in ContinuousStateDerivative order
  std::vector<uint32_t> derivatives;  // their derivatives' valueReferences, same order
  std::vector<Variable> inputs;       // causality input, Float64
  std::vector<Variable> outputs;      // causality output, Float64 (not also a state)
  std::vector<Variable> parameters;   // causality parameter, Float64
  size_t event_indicators = 0;
};

// Parses `folder`/modelDescription.xml. Throws std::runtime_error with what
// is wrong: no such file, malformed XML, fmiVersion not 3.0, no
// <ModelExchange> (Co-Simulation only), array variables, a derivative of an
// unknown variable.
ModelDescription read_model_description(const std::string& folder);

}  // namespace fmu
