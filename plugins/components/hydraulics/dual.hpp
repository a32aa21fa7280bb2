// A value with its derivatives in N inputs (forward mode), and the smooth
// limiters the load-sensing components are written with: each component
// evaluates its law once on Duals and has its row and its analytic Jacobian
// from the same expression, so the two cannot disagree.
//   smin(a, b) = (a + b - sqrt((a - b)^2 + w^2)) / 2   (min, rounded over w)
//   smax(a, b) = (a + b + sqrt((a - b)^2 + w^2)) / 2
// Both are within w/2 of min / max and exact to O(w^2 / |a - b|) away from
// the corner.
#pragma once

#include <array>
#include <cmath>

#include "orifice_flow.hpp"

namespace hyd {

template <int N>
struct Dual {
  double v = 0.0;
  std::array<double, N> d{};

  static Dual constant(double value) {
    Dual x;
    x.v = value;
    return x;
  }
  static Dual input(double value, int k) {
    Dual x;
    x.v = value;
    x.d[static_cast<size_t>(k)] = 1.0;
    return x;
  }
};

template <int N>
Dual<N> operator+(Dual<N> a, const Dual<N>& b) {
  a.v += b.v;
  for (int k = 0; k < N; ++k) a.d[k] += b.d[k];
  return a;
}
template <int N>
Dual<N> operator-(Dual<N> a, const Dual<N>& b) {
  a.v -= b.v;
  for (int k = 0; k < N; ++k) a.d[k] -= b.d[k];
  return a;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> c;
  c.v = a.v * b.v;
  for (int k = 0; k < N; ++k) c.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return c;
}
template <int N>
Dual<N> operator*(double s, Dual<N> a) {
  a.v *= s;
  for (int k = 0; k < N; ++k) a.d[k] *= s;
  return a;
}
template <int N>
Dual<N> operator+(Dual<N> a, double s) {
  a.v += s;
  return a;
}
template <int N>
Dual<N> operator-(Dual<N> a, double s) {
  a.v -= s;
  return a;
}
// f(a) with f' = slope at a.v.
template <int N>
Dual<N> chain(const Dual<N>& a, double value, double slope) {
  Dual<N> c;
  c.v = value;
  for (int k = 0; k < N; ++k) c.d[k] = slope * a.d[k];
  return c;
}
template <int N>
Dual<N> divide(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> c;
  c.v = a.v / b.v;
  for (int k = 0; k < N; ++k) c.d[k] = (a.d[k] - c.v * b.d[k]) / b.v;
  return c;
}
template <int N>
Dual<N> smooth_min(const Dual<N>& a, const Dual<N>& b, double w) {
  const double diff = a.v - b.v, root = std::sqrt(diff * diff + w * w);
  Dual<N> c;
  c.v = 0.5 * (a.v + b.v - root);
  const double da = 0.5 * (1.0 - diff / root), db = 0.5 * (1.0 + diff / root);
  for (int k = 0; k < N; ++k) c.d[k] = da * a.d[k] + db * b.d[k];
  return c;
}
template <int N>
Dual<N> smooth_max(const Dual<N>& a, const Dual<N>& b, double w) {
  const double diff = a.v - b.v, root = std::sqrt(diff * diff + w * w);
  Dual<N> c;
  c.v = 0.5 * (a.v + b.v + root);
  const double da = 0.5 * (1.0 + diff / root), db = 0.5 * (1.0 - diff / root);
  for (int k = 0; k < N; ++k) c.d[k] = da * a.d[k] + db * b.d[k];
  return c;
}
// The orifice law g(dp) of orifice_flow.hpp.
template <int N>
Dual<N> orifice(const OrificeFlow& law, const Dual<N>& dp) {
  return chain(dp, law.g(dp.v), law.slope(dp.v));
}

}  // namespace hyd
