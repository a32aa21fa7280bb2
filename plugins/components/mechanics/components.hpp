// The components of the mechanics plugin library.
#pragma once

#include "monohydra/cpp/subsystem_component.hpp"

namespace mech {

extern const monohydra::SubsystemComponent kSpringDamper;  // spring_damper.cpp
extern const monohydra::SubsystemComponent kMaxwell;       // maxwell_element.cpp

}  // namespace mech
