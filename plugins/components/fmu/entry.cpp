// The FMU import library: one entry symbol, one subsystem factory.
#include "components.hpp"

MONOHYDRA_SUBSYSTEM_PLUGIN(fmu::kFmu);
