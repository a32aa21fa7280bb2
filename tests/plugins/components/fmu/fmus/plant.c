/* The tests' first-order plant: x' = -x/tau + k u (+ bias from bias_time to
 * bias_off_time, two time events, the second announced at the first),
 * y = 2 x. Compiled with MH_WITH_DD it provides its directional derivatives. */
#define NVR 12
#define NX 1
enum { T, X, DX, U, TAU, K, Y, BIAS_TIME, BIAS, OFF_TIME, ON, DONE };
static const unsigned STATE_VR[NX] = {X};
static const unsigned DER_VR[NX] = {DX};
/*                              t    x    dx   u    tau  k    y    bias_time bias off  on   done */
static const double START[NVR] = {0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 0.0};

static void model_compute(double* v) {
  v[DX] = -v[X] / v[TAU] + v[K] * v[U] + (v[ON] != 0.0 ? v[BIAS] : 0.0);
  v[Y] = 2.0 * v[X];
}

static int model_event(double* v, double* next) {
  if (v[BIAS_TIME] < 0.0 || v[DONE] != 0.0) return 0;
  if (v[ON] == 0.0 && v[T] >= v[BIAS_TIME] - 1e-9) v[ON] = 1.0;
  if (v[ON] != 0.0 && v[OFF_TIME] >= 0.0 && v[T] >= v[OFF_TIME] - 1e-9) {
    v[ON] = 0.0;
    v[DONE] = 1.0;
    return 0;
  }
  if (v[ON] == 0.0) {
    *next = v[BIAS_TIME];
    return 1;
  }
  *next = v[OFF_TIME];
  return v[OFF_TIME] >= 0.0;
}

#ifdef MH_WITH_DD
static double model_partial(const double* v, unsigned unknown, unsigned known) {
  if (unknown == DX && known == X) return -1.0 / v[TAU];
  if (unknown == DX && known == U) return v[K];
  if (unknown == Y && known == X) return 2.0;
  return 0.0;
}
#endif

#include "me_skeleton.h"
