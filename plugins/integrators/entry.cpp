// The monohydra-integrators library: one entry symbol, one integrator factory
// that lists its integrators, trapezoidal (the paper's, Eqs. 32-34) first as
// the default.
#include "integrators.hpp"

MONOHYDRA_INTEGRATOR_PLUGIN(integ::kTrapezoidal, integ::kGeneralizedAlpha, integ::kBdf2);
