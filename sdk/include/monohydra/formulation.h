/* monohydra SDK: the Formulation interface.
 *
 * A formulation decides how the mechanism's equations of motion enter the
 * shared Newton step (Sect. 4): it owns `num_unknowns` mechanical unknowns x
 * (e.g. all joint coordinates z_{k+1}, or only the independent ones) and their
 * residual rows r(x). The host owns the subsystem states, the Newton loop, the
 * sparse tangent and its KLU factorization.
 *
 * One step from t_k to t_{k+1} = t_k + dt, as the host drives it:
 *   predict -> [ residual (-> host evaluate_mechanics) , tangent?, solve,
 *                iteration_done? ]* -> accept -> coordinates
 * A step whose Newton iteration fails is abandoned by the host; `accept` is only
 * called for converged steps. */
#ifndef MONOHYDRA_FORMULATION_H
#define MONOHYDRA_FORMULATION_H

#include "monohydra/host.h"
#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MH_FORMULATION_FACTORY_ID "monohydra.formulation-factory/1"

typedef struct mh_formulation {
  uint32_t struct_size; /* sizeof(mh_formulation) of the plugin's SDK */
  const mh_component_descriptor* descriptor;
  void* plugin_data; /* the plugin's own; the host never touches it */

  /* Reads options and sizes itself. *num_unknowns receives the number of
   * mechanical unknowns of the Newton step; tolerance (num_unknowns entries,
   * written after this call returns, so it is NULL here) is set by `start`. */
  mh_status (*setup)(const struct mh_formulation* self, uint32_t* num_unknowns);

  /* Consistent initial conditions at t0 from the model's z0, zd0 (N each): a
   * formulation may correct them (e.g. assemble a closed loop) and computes the
   * initial accelerations. dt is the fixed step. abs_tolerance receives, per
   * unknown, the absolute tolerance on its Newton increment. */
  mh_status (*start)(const struct mh_formulation* self, double t0, double dt, const double* z0,
                     const double* zd0, double* abs_tolerance);

  /* Initial guess x of the unknowns at t_next. */
  mh_status (*predict)(const struct mh_formulation* self, double t_next, double* x);

  /* Residual rows r(x) of the step to t_next (e.g. Eq. 38 or 39). Calls the
   * host's evaluate_mechanics with MH_EVAL_SUBSYSTEMS once, at the iterate. */
  mh_status (*residual)(const struct mh_formulation* self, double t_next, const double* x,
                        double* r);

  /* Optional (NULL: the host differentiates `residual` by forward differences,
   * Eq. 41). d r / d x, dense column-major num_unknowns x num_unknowns, at the x
   * of the last residual call, holding the subsystem states fixed. */
  mh_status (*tangent)(const struct mh_formulation* self, double t_next, const double* x,
                       double* drdx);

  /* Optional: after each Newton update, with the updated x (e.g. Eq. 19). */
  mh_status (*iteration_done)(const struct mh_formulation* self, double t_next, const double* x);

  /* The step to t_next converged at x: update the history (velocities,
   * accelerations, projections such as Eqs. 20-21). */
  mh_status (*accept)(const struct mh_formulation* self, double t_next, const double* x);

  /* The accepted joint coordinates, rates and accelerations (N each). */
  mh_status (*coordinates)(const struct mh_formulation* self, double* z, double* zd, double* zdd);

  void (*destroy)(const struct mh_formulation* self);

  /* Extensions by string id ("name/rev"); NULL when not supported. */
  const void* (*get_extension)(const struct mh_formulation* self, const char* id);
} mh_formulation;

typedef struct mh_formulation_factory {
  uint32_t struct_size;
  uint32_t (*count)(const struct mh_formulation_factory* factory);
  const mh_component_descriptor* (*descriptor)(const struct mh_formulation_factory* factory,
                                               uint32_t index);
  /* Creates the formulation `id`; NULL on failure, after logging through host.
   * `host` outlives the instance. */
  const mh_formulation* (*create)(const struct mh_formulation_factory* factory, const mh_host* host,
                                  const char* id);
} mh_formulation_factory;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_FORMULATION_H */
