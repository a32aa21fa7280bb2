// The ground's surface as a height field: heights z on a square grid of
// spacing s from (x0, y0), between the points a bicubic Catmull-Rom surface,
// which passes through every point, has a continuous slope across the cells
// (the soil's force has a continuous derivative where the edge crosses from
// one cell to the next) and reproduces a plane exactly. Beyond the grid the
// height of its nearest border point holds. Templated on the scalar, as the
// force it enters.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "scalar.hpp"

namespace earth {

class HeightField {
 public:
  HeightField() = default;
  // nx x ny heights, row after row along x (row j at y0 + j s).
  HeightField(double x0, double y0, double spacing, int nx, int ny, std::vector<double> heights)
      : x0_(x0), y0_(y0), spacing_(spacing), nx_(nx), ny_(ny), heights_(std::move(heights)) {}

  template <class S>
  S height(const S& x, const S& y) const {
    S u, v;
    const int i = cell(x, x0_, nx_, u);
    const int j = cell(y, y0_, ny_, v);
    S rows[4];
    for (int r = 0; r < 4; ++r)
      rows[r] = spline(at(i - 1, j - 1 + r), at(i, j - 1 + r), at(i + 1, j - 1 + r),
                       at(i + 2, j - 1 + r), u);
    return spline(rows[0], rows[1], rows[2], rows[3], v);
  }

 private:
  // The cell along one axis the coordinate is in (clamped to the grid) and
  // where in it, 0 to 1.
  template <class S>
  int cell(const S& x, double origin, int n, S& within) const {
    const double last = static_cast<double>(n - 1);
    const S g = (x - origin) / spacing_;
    if (g <= 0.0) {
      within = S(0.0) * g;
      return 0;
    }
    if (g >= last) {
      within = S(1.0) + S(0.0) * g;
      return n - 2;
    }
    const int i = std::min(static_cast<int>(std::floor(value(g))), n - 2);
    within = g - static_cast<double>(i);
    return i;
  }

  // The height at grid point (i, j); a point beyond a border continues the
  // border's slope, so that a plane stays a plane up to the border.
  double at(int i, int j) const {
    if (i < 0) return 2.0 * at(0, j) - at(1, j);
    if (i >= nx_) return 2.0 * at(nx_ - 1, j) - at(nx_ - 2, j);
    if (j < 0) return 2.0 * at(i, 0) - at(i, 1);
    if (j >= ny_) return 2.0 * at(i, ny_ - 1) - at(i, ny_ - 2);
    return heights_[static_cast<size_t>(j) * static_cast<size_t>(nx_) + static_cast<size_t>(i)];
  }

  // Catmull-Rom between p1 (t = 0) and p2 (t = 1), p0 and p3 beside them.
  template <class P, class S>
  static S spline(const P& p0, const P& p1, const P& p2, const P& p3, const S& t) {
    return 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t +
                  (3.0 * (p1 - p2) + p3 - p0) * t * t * t);
  }

  double x0_ = 0.0, y0_ = 0.0, spacing_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<double> heights_;
};

}  // namespace earth
