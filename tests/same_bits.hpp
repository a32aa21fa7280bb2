// Equal to the bit, as "a run equals itself" means: -0.0 is not 0.0, and a
// NaN equals the same NaN.
#pragma once

#include <cstdint>
#include <cstring>

namespace mh::test {

inline bool same_bits(double a, double b) {
  uint64_t x = 0, y = 0;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x == y;
}

}  // namespace mh::test
