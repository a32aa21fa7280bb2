// The components of the earth-moving plugin library (docs/soil.md): the soil
// as a bucket's cutting edge meets it.
#pragma once

#include "monohydra/cpp/subsystem_component.hpp"

namespace earth {

extern const monohydra::SubsystemComponent kBucketSoil;  // bucket_soil.cpp

}  // namespace earth
