// monohydra SDK, optional C++17 helper: the views of the unknowns that cross
// the boundary (formulation.h), made in one expression, each array with its
// length, so neither side writes the struct out field by field.
#pragma once

#include <cstddef>
#include <cstdint>

#include "monohydra/formulation.h"

namespace monohydra {

// The unknowns at time t, read-only: n entries in each array.
inline mh_unknown_values unknown_values(double t, std::size_t n, const double* x, const double* xd,
                                        const double* xdd) noexcept {
  return {sizeof(mh_unknown_values), t, static_cast<uint32_t>(n), x, xd, xdd};
}

// Arrays of n entries that a call writes or corrects in place.
inline mh_unknown_buffers unknown_buffers(std::size_t n, double* x, double* xd,
                                          double* xdd) noexcept {
  return {sizeof(mh_unknown_buffers), static_cast<uint32_t>(n), x, xd, xdd};
}

// The step's coefficients as one value.
inline mh_step_coefficients step_coefficients(double h, double dxd_dx_second, double dxdd_dx_second,
                                              double dxd_dx_first) noexcept {
  return {sizeof(mh_step_coefficients), h, dxd_dx_second, dxdd_dx_second, dxd_dx_first};
}

}  // namespace monohydra
