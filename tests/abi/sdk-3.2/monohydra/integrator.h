/* monohydra SDK: the Integrator interface (the time-step formula).
 *
 * The host owns the step and applies its integrator to every Newton unknown,
 * mechanical or not; formulations and subsystems never see a step formula.
 * An implicit integrator is an affine map, per step, from the unknowns x at
 * the step's end to their rates there:
 *
 *   xd  = c.dxd_dx_second  x + xd_offset    (second-order unknowns)
 *   xdd = c.dxdd_dx_second x + xdd_offset
 *   xd  = c.dxd_dx_first   x + xd_offset    (first-order unknowns)
 *
 * (algebraic unknowns have no rate), so the host solves r(x, xd(x), xdd(x)) = 0
 * by Newton with the tangent dr/dx + dxd_dx dr/dxd + dxdd_dx dr/dxdd. The
 * integrator keeps its own history (the accepted x, xd, xdd it was told).
 *
 * The host drives it:
 *   setup -> restart(t0) -> [ begin_step -> (Newton) -> accept ]* ,
 *   with restart again after a time event or when a formulation redefines its
 *   unknowns; a step that fails is abandoned and the next begin_step starts
 *   again from the last accept or restart.
 *
 * Explicit multi-stage methods give no map: they combine the rates f(t, x) the
 * host computes at stages they choose, through their own operations
 * (mh_explicit_method, mh_integrator.explicit_method). The host drives one
 * step from the accepted t:
 *   [ stage_state(s) -> (the host solves the rates there) -> stage_rates(s) ]
 *     for s = 0 .. num_stages-1 -> finish_step -> (the rates at the end) -> accept
 * At a stage the integrator gives x (and xd of second-order unknowns); the
 * host solves the formulation's residual (and through it the subsystems'
 * rows) for the rest with x held: xdd of second-order unknowns, xd of
 * first-order ones, x of algebraic ones (docs/integrators.md). */
#ifndef MONOHYDRA_INTEGRATOR_H
#define MONOHYDRA_INTEGRATOR_H

#include "monohydra/formulation.h"
#include "monohydra/host.h"
#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MH_INTEGRATOR_FACTORY_ID "monohydra.integrator-factory/3"

/* The problem, handed once at setup (after every command-line override). */
typedef struct mh_integrator_problem {
  uint32_t struct_size;
  uint32_t num_unknowns; /* n */
  const uint8_t* kinds;  /* n: mh_unknown_kind of each unknown */
  double t0;             /* s */
  double dt;             /* the run's step (s); begin_step's h is the step actually taken
                            (this host always takes dt; be ready for a shorter h) */
} mh_integrator_problem;

/* One step's map, written by begin_step into host-owned arrays of
 * num_unknowns. */
typedef struct mh_step_map {
  uint32_t struct_size;
  uint32_t num_unknowns;             /* n: the length of the three arrays */
  mh_step_coefficients coefficients; /* h, dxd_dx_*, dxdd_dx_second */
  double* x_predicted;               /* the Newton iteration's first x */
  double* xd_offset;                 /* see above (ignored for algebraic unknowns) */
  double* xdd_offset;                /* see above (second-order unknowns only) */
} mh_step_map;

struct mh_integrator;

/* The operations of an explicit multi-stage method (see the top of this
 * file). Arrays are the host's, of num_unknowns each. */
typedef struct mh_explicit_method {
  uint32_t struct_size; /* sizeof(mh_explicit_method) of the plugin's SDK */
  uint32_t num_stages;  /* the stages of one step, >= 1 */

  /* Stage `stage` of the step of length h from the last accepted (or
   * restarted) time t: writes its time *t_stage (in [t, t + h]) and its state
   * into out->x (every unknown; the value of an algebraic unknown is the
   * host's starting guess) and out->xd (second-order unknowns; the others'
   * entries are the host's guesses, ignored); out->xdd is NULL. */
  mh_status (*stage_state)(const struct mh_integrator* self, uint32_t stage, double h,
                           double* t_stage, const mh_unknown_buffers* out);

  /* The host's solution at that stage: x with the algebraic unknowns solved,
   * xd (as given for second-order unknowns, solved for first-order ones, 0 for
   * algebraic ones), xdd (solved for second-order unknowns, else 0). */
  mh_status (*stage_rates)(const struct mh_integrator* self, uint32_t stage,
                           const mh_unknown_values* solved);

  /* After the last stage: the step's end state (x, and xd of second-order
   * unknowns; out->xdd is NULL); the host then solves the rates there and
   * calls accept with them (a step that fails is abandoned). */
  mh_status (*finish_step)(const struct mh_integrator* self, double h,
                           const mh_unknown_buffers* out);
} mh_explicit_method;

typedef struct mh_integrator {
  uint32_t struct_size; /* sizeof(mh_integrator) of the plugin's SDK */
  const mh_component_descriptor* descriptor;
  void* plugin_data;

  /* Reads options (host option_*) and sizes itself for the problem. */
  mh_status (*setup)(const struct mh_integrator* self, const mh_integrator_problem* problem);

  void (*destroy)(const struct mh_integrator* self);
  const void* (*get_extension)(const struct mh_integrator* self, const char* id);

  /* Forgets the history and starts from `at` (xd, xdd of unknowns without
   * them are 0): at t0, after a time event, and when a formulation redefines
   * its unknowns. */
  mh_status (*restart)(const struct mh_integrator* self, const mh_unknown_values* at);

  /* The step converged at `accepted` (the map's values, or a formulation's
   * corrections of them; the stages' end for an explicit method). */
  mh_status (*accept)(const struct mh_integrator* self, const mh_unknown_values* accepted);

  /* An implicit method: the map of the step from the last accepted (or
   * restarted) time to t_next = t + h (map->num_unknowns set by the host).
   * NULL for an explicit method. */
  mh_status (*begin_step)(const struct mh_integrator* self, double t_next, double h,
                          mh_step_map* map);

  /* An explicit method: its stage operations (lives as long as the
   * instance). NULL for an implicit method. Exactly one of begin_step and
   * explicit_method is given. */
  const mh_explicit_method* explicit_method;
} mh_integrator;

typedef struct mh_integrator_factory {
  uint32_t struct_size;
  uint32_t (*count)(const struct mh_integrator_factory* factory);
  const mh_component_descriptor* (*descriptor)(const struct mh_integrator_factory* factory,
                                               uint32_t index);
  /* Creates the integrator `id`; NULL on failure, after logging through host. */
  const mh_integrator* (*create)(const struct mh_integrator_factory* factory, const mh_host* host,
                                 const char* id);
  /* Optional (NULL: none): as mh_subsystem_factory.example_model. */
  const char* (*example_model)(const struct mh_integrator_factory* factory, uint32_t index);
} mh_integrator_factory;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_INTEGRATOR_H */
