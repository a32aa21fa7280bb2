/* The tests' PI controller with back-calculation anti-windup, the equations
 * of monohydra-control's pi-controller (docs/control.md):
 *   e = setpoint - measurement, v = kp e + i, u = min(max(v, lo), hi),
 *   di/dt = ki e + (u - v) / Tt. */
#define NVR 11
#define NX 1
enum { T, I, DI, SETPOINT, MEASUREMENT, KP, KI, LO, HI, TT, U };
static const unsigned STATE_VR[NX] = {I};
static const unsigned DER_VR[NX] = {DI};
static const double START[NVR] = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, -1e300, 1e300, 1.0, 0.0};

static void model_compute(double* v) {
  const double e = v[SETPOINT] - v[MEASUREMENT];
  const double unsaturated = v[KP] * e + v[I];
  const double u = unsaturated < v[LO] ? v[LO] : unsaturated > v[HI] ? v[HI] : unsaturated;
  v[U] = u;
  v[DI] = v[KI] * e + (u - unsaturated) / v[TT];
}

static int model_event(double* v, double* next) {
  (void)v;
  (void)next;
  return 0;
}

#include "me_skeleton.h"
