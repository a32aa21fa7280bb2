// Smooth (C1) switches for the soil's force: the coupled step solves it in
// one Newton iteration only if the force has a continuous derivative in the
// edge's depth, rake and velocity. Each is exact outside its narrow band, so
// that away from the surface, the rake's limits and rest the force is the
// earth-moving equation's own value.
#pragma once

#include <cmath>

namespace earth {

// 0 for x <= 0, x for x >= width, and between them the cubic 2 x^2 / width -
// x^3 / width^2 that joins both with value and slope.
template <class S>
S ramp(const S& x, double width) {
  if (x <= 0.0) return S(0.0) * x;
  if (x >= width) return x;
  return x * x * (2.0 / width) - x * x * x / (width * width);
}

// 0 for x <= 0, 1 for x >= width, the smoothstep 3 u^2 - 2 u^3 (u = x /
// width) between: a pressure that acts as soon as the edge is in the soil.
template <class S>
S engaged(const S& x, double width) {
  if (x <= 0.0) return S(0.0) * x;
  if (x >= width) return S(1.0) + S(0.0) * x;
  const S u = x / width;
  return u * u * (3.0 - 2.0 * u);
}

// x kept in [lo, hi], rounded off over `width` inside each limit: x itself
// on [lo + width, hi - width].
template <class S>
S soft_clamp(const S& x, double lo, double hi, double width) {
  const S floored = lo + ramp<S>(x - lo, width);
  return hi - ramp<S>(hi - floored, width);
}

// How much of the resistance a speed v along the cut mobilises: 0 at rest or
// backwards, tanh(v / scale)^2 forwards (1 to 1e-10 beyond 12 scales), so
// that a blade pushed harder than the soil's passive force moves and one
// pushed less creeps at about `scale`.
template <class S>
S mobilised(const S& v, double scale) {
  using std::tanh;
  if (v <= 0.0) return S(0.0) * v;
  const S t = tanh(v / scale);
  return t * t;
}

}  // namespace earth
