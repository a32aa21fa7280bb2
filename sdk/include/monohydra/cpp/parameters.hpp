// monohydra SDK, optional C++17 helper: the parameters extension
// (parameters.h) of a component class T, made by SubsystemAdapter
// (subsystem_component.hpp) when T lists its parameters once,
//
//   static constexpr monohydra::ParameterSpec kParameters[] = {
//       {"bulk_modulus", "Pa", monohydra::kPositive, HUGE_VAL}, ...};
//   double parameter(uint32_t index) const;            // its value now
//   void set_parameter(uint32_t index, double value);  // and what derives from it
//
// The adapter checks the index, finiteness and [lower, upper] before
// set_parameter sees a value, and logs a refusal naming the key and the range.
#pragma once

#include <cstdint>
#include <limits>

#include "monohydra/parameters.h"

namespace monohydra {

struct ParameterSpec {
  const char* key;
  const char* unit;
  double lower, upper;  // both included
};

// The smallest positive double: the lower bound of a parameter that must be positive.
inline constexpr double kPositive = std::numeric_limits<double>::min();

}  // namespace monohydra
