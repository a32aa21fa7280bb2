/* monohydra SDK: the Formulation interface.
 *
 * A formulation decides how the mechanism's equations of motion enter the
 * shared Newton step (Sect. 4): it declares Newton unknowns x (add_unknown:
 * e.g. all joint coordinates, only the independent ones, or coordinates and
 * multipliers) and writes their residual rows r(x, xd, xdd). It never sees a
 * step formula: the host's integrator (integrator.h) ties xd and xdd of the
 * step's end to x, and the host owns the subsystem states, the Newton loop,
 * the sparse tangent and its factorization.
 *
 * One step to t_next, as the host drives it:
 *   begin_step -> [ residual (-> host evaluate_mechanics), mechanics_map?,
 *                   tangent?, solve, iteration_done? ]* -> accept ->
 *   coordinates, write_outputs?
 * A step whose Newton iteration fails is abandoned: accept is only called for
 * converged steps, and the next begin_step starts again from the last accepted
 * state. */
#ifndef MONOHYDRA_FORMULATION_H
#define MONOHYDRA_FORMULATION_H

#include "monohydra/host.h"
#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MH_FORMULATION_FACTORY_ID "monohydra.formulation-factory/3"

/* How the integrator ties the rates at the step's end to the unknowns x there:
 * xd = dxd_dx x + (offset), xdd = dxdd_dx x + (offset), by the unknown's kind.
 * A formulation needs them for corrections that mix levels (e.g. the
 * projections' W = M' + C dxd_dx / dxdd_dx + K / dxdd_dx, Eqs. 20-21) and to
 * scale an algebraic unknown's tolerance with the step. */
typedef struct mh_step_coefficients {
  uint32_t struct_size;
  double h;              /* the step t_next - t_k (s) */
  double dxd_dx_second;  /* c_v of second-order unknowns, e.g. 2 / h (trapezoidal) */
  double dxdd_dx_second; /* c_a, e.g. 4 / h^2 */
  double dxd_dx_first;   /* of first-order unknowns, e.g. 2 / h */
} mh_step_coefficients;

/* The Newton unknowns at one time, as the host hands them in: every array has
 * num_unknowns entries (xd and xdd of unknowns without them hold 0). */
typedef struct mh_unknown_values {
  uint32_t struct_size;
  double t;              /* s */
  uint32_t num_unknowns; /* n */
  const double* x;
  const double* xd;
  const double* xdd;
} mh_unknown_values;

/* Host-owned arrays of num_unknowns each that a call writes (start) or
 * corrects in place (accept). */
typedef struct mh_unknown_buffers {
  uint32_t struct_size;
  uint32_t num_unknowns; /* n */
  double* x;
  double* xd;
  double* xdd;
} mh_unknown_buffers;

/* begin_step's argument: the step's map and the integrator's prediction. For
 * a stage of an explicit integrator there is no map: h is the stage's step and
 * the three rates are 0. */
typedef struct mh_step_begin {
  uint32_t struct_size;
  mh_step_coefficients coefficients;
  mh_unknown_values predicted; /* t = t_next */
} mh_step_begin;

/* tangent's blocks: dense, column-major num_unknowns x num_unknowns each, zero
 * on entry (see MH_EXT_COORDINATE_UNKNOWNS for the sparse case);
 * column_given has num_unknowns entries, 0 on entry. */
typedef struct mh_tangent_blocks {
  uint32_t struct_size;
  uint32_t num_unknowns; /* n */
  double* dr_dx;
  double* dr_dxd;
  double* dr_dxdd;
  uint8_t* column_given;
} mh_tangent_blocks;

/* mechanics_map's blocks, column-major, zero on entry: dz_dx, dzd_dx and
 * dzd_dxd are num_coordinates x num_unknowns (NULL when the host needs none of
 * them), dr_dQ is num_unknowns x num_coordinates. */
typedef struct mh_mechanics_map {
  uint32_t struct_size;
  uint32_t num_coordinates; /* N */
  uint32_t num_unknowns;    /* n */
  double* dz_dx;
  double* dzd_dx;
  double* dzd_dxd;
  double* dr_dQ;
} mh_mechanics_map;

/* The joint coordinates, rates and accelerations a formulation writes
 * (coordinates): num_coordinates each. */
typedef struct mh_coordinate_buffers {
  uint32_t struct_size;
  uint32_t num_coordinates; /* N */
  double* z;
  double* zd;
  double* zdd;
} mh_coordinate_buffers;

/* accept's flags (out). */
#define MH_ACCEPT_REDEFINED                                                    \
  0x1u /* the unknowns now stand for other quantities (e.g. a new choice of    \
          independent coordinates); x, xd, xdd hold their values, and the host \
          restarts the integrator from them */

/* Formulation extension (get_extension with this id returns any non-NULL
 * pointer when it holds): the unknowns are the joint coordinates, x = z in
 * their order (n = N), and the rows couple them only as the mechanics do:
 * coordinates i and j when one joint is an ancestor of the other (M', K, C of
 * Eqs. 5-12), when both move a body of the same cut joint (its constraint
 * terms), or both move points of the same subsystem instance (its forces).
 * The host then takes the tangent's mechanical block sparse in that pattern
 * and ignores the formulation's tangent entries outside it: it zeroes
 * dr_dx, dr_dxd, dr_dxdd on entry only inside the pattern (outside, they hold
 * whatever was written there before). Without it the block is dense. */
#define MH_EXT_COORDINATE_UNKNOWNS "monohydra.coordinate-unknowns/1"

/* Formulation extension (any non-NULL pointer when it holds; with
 * MH_EXT_COORDINATE_UNKNOWNS): the rows are the equations of motion of the
 * tree, r = M'(x) xdd - Q'(x, xd) (Eq. 12) with nothing added, so that
 * dr/dxdd = M'. The host may then take the integrator's dxdd_dx times M' as
 * Newton's matrix and solve it by the articulated-body recursion in O(N)
 * (solver.newton: articulated) instead of assembling the tangent. */
#define MH_EXT_EQUATIONS_OF_MOTION "monohydra.equations-of-motion/1"

typedef struct mh_formulation {
  uint32_t struct_size; /* sizeof(mh_formulation) of the plugin's SDK */
  const mh_component_descriptor* descriptor;
  void* plugin_data; /* the plugin's own; the host never touches it */

  /* Reads options (host option_*), the mechanism (host mech_info: sizes,
   * names, t0, the assembled z0 and zd0) and declares its unknowns
   * (add_unknown) and outputs (add_output). */
  mh_status (*setup)(const struct mh_formulation* self);

  void (*destroy)(const struct mh_formulation* self);

  /* Extensions by string id ("name/rev"); NULL when not supported. */
  const void* (*get_extension)(const struct mh_formulation* self, const char* id);

  /* Consistent initial conditions at t0: x0, xd0, xdd0 of the unknowns into
   * `out` (xd0, xdd0 of algebraic unknowns are ignored). */
  mh_status (*start)(const struct mh_formulation* self, const mh_unknown_buffers* out);

  /* Optional: a step to t_next begins from the last accepted state, with the
   * step's coefficients and the integrator's prediction (e.g. to reset
   * multipliers, to estimate dependent coordinates, or to scale tolerances
   * with h). */
  mh_status (*begin_step)(const struct mh_formulation* self, const mh_step_begin* step);

  /* Residual rows r(x, xd, xdd) at `at` (r: at->num_unknowns entries; e.g.
   * Eqs. 38-39 without their dt^2/4). Calls the host's evaluate_mechanics with
   * MH_EVAL_SUBSYSTEMS once, at the iterate. Pure: no history changes. */
  mh_status (*residual)(const struct mh_formulation* self, const mh_unknown_values* at, double* r);

  /* Optional (NULL: the host differences `residual` along the integrator's
   * map, x perturbed and xd, xdd following it, Eqs. 40-41). Analytic blocks
   * at `at`, the arguments of the last residual call, holding the subsystem
   * states fixed. The formulation sets column_given[j] = 1 for each column j
   * it wrote in all three blocks; the host differences the others. */
  mh_status (*tangent)(const struct mh_formulation* self, const mh_unknown_values* at,
                       const mh_tangent_blocks* out);

  /* Optional: after each Newton update, with the updated unknowns (e.g. Eq. 19). */
  mh_status (*iteration_done)(const struct mh_formulation* self, const mh_unknown_values* at);

  /* The step to t converged at `values`: update the history. The formulation
   * may correct xd and xdd in place (e.g. the projections of Eqs. 20-21), or
   * redefine its unknowns (*flags |= MH_ACCEPT_REDEFINED, with x, xd, xdd
   * rewritten); the integrator continues from what it leaves there. *flags is
   * 0 on entry. MH_DISCARD: the step is not accepted (nothing was committed)
   * and the host treats it as a failed step. The coefficients are those of the
   * step's map (every implicit integrator gives all three > 0). */
  mh_status (*accept)(const struct mh_formulation* self, double t,
                      const mh_step_coefficients* coefficients, const mh_unknown_buffers* values,
                      uint32_t* flags);

  /* The accepted joint coordinates, rates and accelerations into `out`. */
  mh_status (*coordinates)(const struct mh_formulation* self, const mh_coordinate_buffers* out);

  /* Optional: writes the values of the outputs it declared, at the accepted
   * state (after start and after each accept), into outputs[index]
   * (num_outputs: the run's total). */
  mh_status (*write_outputs)(const struct mh_formulation* self, double* outputs,
                             uint32_t num_outputs);

  /* Optional: how the mechanics of the last residual call depended on the
   * unknowns, so that the host couples the subsystems with points to them
   * without differences: no residual is then differenced in a state column,
   * nor in a mechanical column that `tangent` gave (with `tangent` giving
   * every column, none at all). Called right after that residual call, before
   * any difference the host takes. dz_dx, dzd_dx, dzd_dxd are the partial
   * derivatives of the z and zd it passed to evaluate_mechanics with respect
   * to x and xd; dr_dQ those of its rows with respect to the generalized
   * applied forces Q' it got back (e.g. -I for r = M' zdd - Q'). */
  mh_status (*mechanics_map)(const struct mh_formulation* self, const mh_mechanics_map* out);
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
  /* Optional (NULL: none): the YAML text of a small model file that uses
   * component `index`, or NULL when it declares none; it lives as long as the
   * library. `monohydra check PLUGIN.so` without a model checks the component
   * on it. The same member, in the same place, in every factory. */
  const char* (*example_model)(const struct mh_formulation_factory* factory, uint32_t index);
} mh_formulation_factory;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_FORMULATION_H */
