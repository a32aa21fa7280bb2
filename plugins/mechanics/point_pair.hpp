// The geometry two-point elements share: the distance between point a and
// point b, its rate, and a tension applied to both bodies along the line.
#pragma once

#include <cmath>

#include "monohydra/subsystem.h"

namespace mech {

struct PointPair {
  double length = 0.0;            // |p_b - p_a|, m
  double rate = 0.0;              // d length / dt, m/s
  double e[3] = {0.0, 0.0, 0.0};  // unit vector from a to b

  // Reads points 0 (a) and 1 (b) of `eval`. Returns false when they coincide
  // (the direction is then undefined).
  bool measure(const mh_subsystem_eval* eval);
  // Tension T > 0 pulls the points together: +T e on a, -T e on b.
  void apply_tension(const mh_subsystem_eval* eval, double tension) const;
};

}  // namespace mech
