/* monohydra SDK: the Subsystem interface (springs, dampers, hydraulic volumes,
 * valves, cylinders, ...).
 *
 * A subsystem instance may own states y (e.g. a pressure) and may be attached
 * to body points. Its equations are written in residual form: every state i has
 * one residual row, the SUM of the contributions of every instance that touches
 * it, and the step solves sum = 0 with y_{k+1} and ydot_{k+1} tied by the
 * host's integrator (the trapezoidal rule by default, Eqs. 32-34). An instance adds to the rows of
 * the states it touches (its own, and others found with find_state) and applies forces at its
 * points; the host turns those into generalized forces (Eq. 10).
 *
 * The sparsity of the shared tangent follows from setup: an instance's rows
 * depend on the states it touches and, if it has points, on the mechanical
 * unknowns; the mechanical rows depend on its states if it has points. */
#ifndef MONOHYDRA_SUBSYSTEM_H
#define MONOHYDRA_SUBSYSTEM_H

#include "monohydra/host.h"
#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MH_SUBSYSTEM_FACTORY_ID "monohydra.subsystem-factory/3"

typedef struct mh_subsystem_eval {
  uint32_t struct_size;
  double t;              /* s */
  uint32_t num_states;   /* length of y, ydot and residual */
  const double* y;       /* every subsystem state, by global index */
  const double* ydot;    /* their rates */
  double* residual;      /* every state's row: add this instance's contributions */
  uint32_t num_points;   /* this instance's points */
  const double* point_p; /* 3 per point: world position (m) */
  const double* point_v; /* 3 per point: world velocity (m/s) */
  double* point_f;       /* 3 per point: force on the body at the point (N, world);
                            zero on entry */
  uint32_t num_outputs;  /* length of outputs */
  double* outputs;       /* every instance's outputs, by index: write your own */
  uint32_t num_touched;  /* the states this instance touches (its own, those found
                            with find_state, its ports' nodes): the size of its
                            jacobian blocks, in first-call order without repeats */
} mh_subsystem_eval;

typedef struct mh_subsystem {
  uint32_t struct_size; /* sizeof(mh_subsystem) of the plugin's SDK */
  const mh_component_descriptor* descriptor;
  void* plugin_data;

  /* Reads options, declares states (add_state), ports (add_port) and outputs
   * (add_output), finds other instances' states (find_state) and attaches to
   * points (add_point). Instances are set up in
   * model order; find_state only finds states of instances set up before. */
  mh_status (*setup)(const struct mh_subsystem* self);

  void (*destroy)(const struct mh_subsystem* self);
  const void* (*get_extension)(const struct mh_subsystem* self, const char* id);

  /* Adds this instance's contributions to the residual rows and its point
   * forces, at the state and kinematics in `eval`. Pure: no history changes. */
  mh_status (*evaluate)(const struct mh_subsystem* self, const mh_subsystem_eval* eval);

  /* Optional (NULL: forward differences). Partial derivatives of this instance's
   * contributions with respect to the states it touches: n x n with
   * n = eval->num_touched, column-major (entry (a, b) at b n + a: row a, column
   * b, both in the touched order), into d_dy (wrt y) and d_dydot (wrt ydot);
   * both zero on entry. */
  mh_status (*jacobian)(const struct mh_subsystem* self, const mh_subsystem_eval* eval,
                        double* d_dy, double* d_dydot);

  /* Optional: energy stored in the instance (J) and the power it dissipates (W,
   * >= 0), for the energy balance. */
  mh_status (*energy)(const struct mh_subsystem* self, const mh_subsystem_eval* eval,
                      double* stored, double* dissipation);

  /* Optional: the step converged at `eval` (e.g. update hysteresis). */
  mh_status (*accept)(const struct mh_subsystem* self, const mh_subsystem_eval* eval);

  /* Optional (NULL: the host differences `evaluate` in the point positions and
   * velocities). The derivatives of this instance's point forces with respect
   * to its points' world positions and velocities, at `eval`, states held:
   * 3P x 3P each (P = eval->num_points), column-major, row 3a+i = force on
   * point a, component i; column 3b+j = point b, component j. Zero on entry. */
  mh_status (*point_force_jacobian)(const struct mh_subsystem* self, const mh_subsystem_eval* eval,
                                    double* dF_dp, double* dF_dv);

  /* Optional (NULL: the host differences `evaluate` in the points' motion and
   * the states, this instance alone). How this instance couples to the
   * mechanics, at `eval`, all column-major and zero on entry, with n =
   * eval->num_touched and P = eval->num_points: the derivatives of its rows
   * with respect to its points' world positions and velocities, dR_dp and
   * dR_dv (n x 3P: row a = the a-th state it touches, column 3b+j = point b,
   * component j), and of its point forces with respect to the states it
   * touches and their rates, dF_dy and dF_dydot (3P x n: row 3b+i = force on
   * point b, component i, column a = the a-th state it touches). */
  mh_status (*coupling_jacobian)(const struct mh_subsystem* self, const mh_subsystem_eval* eval,
                                 double* dR_dp, double* dR_dv, double* dF_dy, double* dF_dydot);
} mh_subsystem;

typedef struct mh_subsystem_factory {
  uint32_t struct_size;
  uint32_t (*count)(const struct mh_subsystem_factory* factory);
  const mh_component_descriptor* (*descriptor)(const struct mh_subsystem_factory* factory,
                                               uint32_t index);
  const mh_subsystem* (*create)(const struct mh_subsystem_factory* factory, const mh_host* host,
                                const char* id);
  /* Optional (NULL: none): the YAML text of a small model file that uses
   * component `index` with example options, or NULL when it declares none; it
   * lives as long as the library. `monohydra check PLUGIN.so` without a model
   * checks the component on it (docs/sdk.md). */
  const char* (*example_model)(const struct mh_subsystem_factory* factory, uint32_t index);
} mh_subsystem_factory;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_SUBSYSTEM_H */
