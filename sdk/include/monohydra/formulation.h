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
 *   begin_step -> [ residual (-> host evaluate_mechanics), tangent?, solve,
 *                   iteration_done? ]* -> accept -> coordinates, write_outputs?
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

#define MH_FORMULATION_FACTORY_ID "monohydra.formulation-factory/2"

/* How the integrator ties the rates at the step's end to the unknowns x there:
 * xd = dxd_dx x + (offset), xdd = dxdd_dx x + (offset), by the unknown's kind.
 * A formulation needs them only for corrections that mix levels (e.g. the
 * projections' W = M' + C dxd_dx / dxdd_dx + K / dxdd_dx, Eqs. 20-21). */
typedef struct mh_step_coefficients {
  uint32_t struct_size;
  double h;              /* the step t_next - t_k (s) */
  double dxd_dx_second;  /* of second-order unknowns, e.g. 2 / h (trapezoidal) */
  double dxdd_dx_second; /* e.g. 4 / h^2 */
  double dxd_dx_first;   /* of first-order unknowns, e.g. 2 / h */
} mh_step_coefficients;

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

typedef struct mh_formulation {
  uint32_t struct_size; /* sizeof(mh_formulation) of the plugin's SDK */
  const mh_component_descriptor* descriptor;
  void* plugin_data; /* the plugin's own; the host never touches it */

  /* Reads options (host option_*), the mechanism (host mech_info: sizes,
   * names, t0, the assembled z0 and zd0) and declares its unknowns
   * (add_unknown) and outputs (add_output). */
  mh_status (*setup)(const struct mh_formulation* self);

  /* Consistent initial conditions at t0: x0, xd0, xdd0 of the unknowns (n
   * each; xd0, xdd0 of algebraic unknowns are ignored). */
  mh_status (*start)(const struct mh_formulation* self, double* x0, double* xd0, double* xdd0);

  /* Optional: a step to t_next begins from the last accepted state; x, xd,
   * xdd are the integrator's prediction (e.g. to reset multipliers, or to
   * estimate dependent coordinates). */
  mh_status (*begin_step)(const struct mh_formulation* self, double t_next, const double* x,
                          const double* xd, const double* xdd);

  /* Residual rows r(x, xd, xdd) at t (n each; e.g. Eqs. 38-39 without their
   * dt^2/4). Calls the host's evaluate_mechanics with MH_EVAL_SUBSYSTEMS once,
   * at the iterate. Pure: no history changes. */
  mh_status (*residual)(const struct mh_formulation* self, double t, const double* x,
                        const double* xd, const double* xdd, double* r);

  /* Optional (NULL: the host differences `residual` along the integrator's
   * map, x perturbed and xd, xdd following it, Eqs. 40-41). Analytic
   * blocks at the arguments of the last residual call, holding the subsystem
   * states fixed: dr_dx, dr_dxd, dr_dxdd, dense column-major n x n, zero on
   * entry. The formulation sets column_given[j] = 1 for each column j it wrote
   * in all three blocks; the host differences the others. */
  mh_status (*tangent)(const struct mh_formulation* self, double t, const double* x,
                       const double* xd, const double* xdd, double* dr_dx, double* dr_dxd,
                       double* dr_dxdd, uint8_t* column_given);

  /* Optional: after each Newton update, with the updated unknowns (e.g. Eq. 19). */
  mh_status (*iteration_done)(const struct mh_formulation* self, double t, const double* x,
                              const double* xd, const double* xdd);

  /* The step to t converged at x, xd, xdd: update the history. The
   * formulation may correct xd and xdd in place (e.g. the projections of Eqs.
   * 20-21), or redefine its unknowns (*flags |= MH_ACCEPT_REDEFINED, with x,
   * xd, xdd rewritten); the integrator continues from what it leaves there.
   * *flags is 0 on entry. MH_DISCARD: the step is not accepted (nothing was
   * committed) and the host treats it as a failed step. The coefficients are
   * those of the step's map (every implicit integrator gives all three > 0). */
  mh_status (*accept)(const struct mh_formulation* self, double t,
                      const mh_step_coefficients* coefficients, double* x, double* xd, double* xdd,
                      uint32_t* flags);

  /* The accepted joint coordinates, rates and accelerations (N each). */
  mh_status (*coordinates)(const struct mh_formulation* self, double* z, double* zd, double* zdd);

  /* Optional: writes the values of the outputs it declared, at the accepted
   * state (after start and after each accept), into outputs[index]
   * (num_outputs: the run's total). */
  mh_status (*write_outputs)(const struct mh_formulation* self, double* outputs,
                             uint32_t num_outputs);

  void (*destroy)(const struct mh_formulation* self);

  /* Extensions by string id ("name/rev"); NULL when not supported. */
  const void* (*get_extension)(const struct mh_formulation* self, const char* id);

  /* -- ABI 2.2 (the host reads it only when struct_size reaches it) ---------- */
  /* Optional: how the mechanics of the last residual call depended on the
   * unknowns, so that the host couples the subsystems with points to them
   * without differences: no residual is then differenced in a state column,
   * nor in a mechanical column that `tangent` gave (with `tangent` giving
   * every column, none at all). Called right after that residual call, before
   * any difference the host takes. At the arguments of the last residual
   * call: dz_dx, dzd_dx, dzd_dxd (N x n each, column-major) are the partial
   * derivatives of the z and zd it passed to evaluate_mechanics with respect to
   * x and xd; dr_dQ (n x N, column-major) those of its rows with respect to the
   * generalized applied forces Q' it got back (e.g. -I for r = M' zdd - Q').
   * All zero on entry. dz_dx, dzd_dx and dzd_dxd are NULL when the host needs
   * none of them (when `tangent` gave no mechanical column). */
  mh_status (*mechanics_map)(const struct mh_formulation* self, double* dz_dx, double* dzd_dx,
                             double* dzd_dxd, double* dr_dQ);
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
