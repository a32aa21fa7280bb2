// The modelDescription.xml of an exported FMU, FMI 3.0 (fmi3ModelDescription
// schema, 2.4) or FMI 2.0 (fmiModelDescription, 2.2), written from the
// variable table the binary itself uses (packed_model.hpp).
#pragma once

#include <string>
#include <vector>

#include "packed_model.hpp"

namespace mh::fmu {

struct Description {
  int fmi_version = 3;           // 3 or 2
  std::string model_name;        // the model's name:
  std::string model_identifier;  // the binary's file name without .so
  std::string token;             // instantiationToken (3.0) / guid (2.0)
  std::string generation_tool;   // "monohydra 0.9.0"
  double dt = 0.0, t_end = 0.0;  // fixedInternalStepSize, DefaultExperiment
  std::vector<FmuVariable> variables;
};

std::string model_description_xml(const Description& d);

}  // namespace mh::fmu
