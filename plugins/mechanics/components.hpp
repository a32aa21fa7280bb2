// The components of the mechanics plugin library.
#pragma once

#include "monohydra/subsystem.h"

namespace mech {

extern const mh_component_descriptor kSpringDamperDescriptor;
extern const mh_component_descriptor kMaxwellDescriptor;

const mh_subsystem* create_spring_damper(const mh_host* host);
const mh_subsystem* create_maxwell_element(const mh_host* host);

}  // namespace mech
