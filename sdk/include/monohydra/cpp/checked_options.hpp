// monohydra SDK, optional C++17 helper (header-only): a number option read and
// checked in one call. When the value fails the check, the host reports it
// with the file and line it came from and `expected` (option_error), and the
// call returns MH_ERROR; a missing optional key yields `fallback` unchecked.
//
//   if (monohydra::positive_option(host, "area", 1, 0.0, "a positive area (m^2)", &a) != MH_OK)
//     return MH_ERROR;
#pragma once

#include <cmath>

#include "monohydra/cpp/services.hpp"
#include "monohydra/host.h"

namespace monohydra {

namespace checked_detail {

template <class Check>
mh_status read(const mh_host* host, const char* key, int required, double fallback,
               const char* expected, double* out, Check ok) {
  if (options(host).option_number(host, key, required, fallback, out) != MH_OK) return MH_ERROR;
  if (!ok(*out)) return options(host).option_error(host, key, expected);
  return MH_OK;
}

}  // namespace checked_detail

// Finite and > 0.
inline mh_status positive_option(const mh_host* host, const char* key, int required,
                                 double fallback, const char* expected, double* out) {
  return checked_detail::read(host, key, required, fallback, expected, out,
                              [](double v) { return std::isfinite(v) && v > 0.0; });
}

// Finite and >= 0.
inline mh_status nonnegative_option(const mh_host* host, const char* key, int required,
                                    double fallback, const char* expected, double* out) {
  return checked_detail::read(host, key, required, fallback, expected, out,
                              [](double v) { return std::isfinite(v) && v >= 0.0; });
}

// Finite.
inline mh_status finite_option(const mh_host* host, const char* key, int required, double fallback,
                               const char* expected, double* out) {
  return checked_detail::read(host, key, required, fallback, expected, out,
                              [](double v) { return std::isfinite(v); });
}

}  // namespace monohydra
