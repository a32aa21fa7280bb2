// The integrators of the monohydra-integrators library (docs/integrators.md),
// each defined in its own file; entry.cpp lists them, the default first.
#pragma once

#include "monohydra/cpp/integrator_plugin.hpp"

namespace integ {

extern const monohydra::IntegratorComponent kTrapezoidal;       // trapezoidal.cpp
extern const monohydra::IntegratorComponent kGeneralizedAlpha;  // generalized_alpha.cpp
extern const monohydra::IntegratorComponent kBdf2;              // bdf2.cpp

}  // namespace integ
