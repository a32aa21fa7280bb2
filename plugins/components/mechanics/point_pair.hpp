// The geometry two-point elements share: the distance between point a and
// point b, its rate, and a tension applied to both bodies along the line.
#pragma once

#include <cmath>

#include "monohydra/host.h"
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
  // The length's and its rate's derivatives in point b's position (those in
  // point a's are their negatives; the rate's in b's velocity is e):
  // dl/dp_b = e, dldot/dp_b = (v_b - v_a)^T (I - e e^T) / l.
  void rate_gradient(const mh_subsystem_eval* eval, double* drate_dpb) const;
  // d(point forces)/d(points' positions, velocities) (6 x 6 column-major, the
  // layout of point_force_jacobian, added to dF_dp, dF_dv) of the tension T
  // with dT/dl and dT/dldot, states held.
  void tension_jacobian(const mh_subsystem_eval* eval, double tension, double dT_dl,
                        double dT_drate, double* dF_dp, double* dF_dv) const;
};

// Declares the element's look for a host that draws the run (visual.h): a
// link between points a and b (MH_OK without such a host).
mh_status declare_link(const mh_host* host, int32_t point_a, int32_t point_b);

}  // namespace mech
