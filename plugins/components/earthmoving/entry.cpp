// The earth-moving plugin library: one entry symbol, one subsystem factory
// that lists its components.
#include "components.hpp"

MONOHYDRA_SUBSYSTEM_PLUGIN(earth::kBucketSoil);
