// monohydra SDK, optional C++17 helper (header-only): the spec structs of
// host.h filled in one expression, with struct_size set to this SDK's sizeof
// and every field a plugin does not name zero (no role, no range):
//
//   const mh_state_spec spec = monohydra::state_spec("p", "Pa", 1e5, 1e-2);
//   if (monohydra::subsystem_setup(host).add_state(host, &spec, &p_) != MH_OK) return MH_ERROR;
#pragma once

#include <cstdint>

#include "monohydra/host.h"

namespace monohydra {

// A state (add_state) without a role or a range.
inline mh_state_spec state_spec(const char* name, const char* unit, double initial,
                                double abs_tolerance) noexcept {
  mh_state_spec spec{};
  spec.struct_size = sizeof(mh_state_spec);
  spec.name = name;
  spec.unit = unit;
  spec.initial = initial;
  spec.abs_tolerance = abs_tolerance;
  return spec;
}

// An output (add_output) of kind `kind` (mh_output_kind), without a role or a range.
inline mh_output_spec output_spec(const char* name, const char* unit,
                                  uint32_t kind = MH_OUTPUT_SIGNAL) noexcept {
  mh_output_spec spec{};
  spec.struct_size = sizeof(mh_output_spec);
  spec.name = name;
  spec.unit = unit;
  spec.kind = kind;
  return spec;
}

// A formulation's Newton unknown (add_unknown).
inline mh_unknown_spec unknown_spec(const char* name, const char* unit, mh_unknown_kind kind,
                                    double abs_tolerance) noexcept {
  mh_unknown_spec spec{};
  spec.struct_size = sizeof(mh_unknown_spec);
  spec.name = name;
  spec.unit = unit;
  spec.kind = static_cast<uint32_t>(kind);
  spec.abs_tolerance = abs_tolerance;
  return spec;
}

}  // namespace monohydra
