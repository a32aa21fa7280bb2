// The FMU import library (docs/fmi.md, "Importing a Model Exchange FMU"):
// one component, `fmu`, that runs an FMI 3.0 Model Exchange FMU's equations
// inside the monolithic Newton step.
#pragma once

#include "monohydra/cpp/subsystem_component.hpp"

namespace fmu {

extern const monohydra::SubsystemComponent kFmu;  // fmu_component.cpp

}  // namespace fmu
