// The plain value of a scalar the soil's functions are written for: a double
// itself, or an automatic-differentiation scalar without its derivatives,
// where a branch, a cell index or the failure plane's search needs a number.
#pragma once

namespace earth {

inline double value(double x) {
  return x;
}

template <class S>
double value(const S& x) {
  return x.value();
}

}  // namespace earth
