// An explicit integrator's stability check in words, for run's summary and
// compare's table and report: "unstable: dt = 1 ms, |R| = 1.3 (lambda = ...),
// stable below ~ 0.42 ms".
#pragma once

#include <string>

#include "monohydra/core/explicit_stability.hpp"

namespace mh::cli {

// "" when no check ran (an implicit integrator, or the check is off).
std::string stability_text(const ExplicitStability& s);
// What the checks cost: "1 check, 0.152 ms CPU".
std::string stability_cost_text(const ExplicitStability& s);

}  // namespace mh::cli
