/* monohydra SDK: the residual of a tree's equations of motion, computed in
 * O(N) by the host.
 *
 * evaluate_mechanics(MH_EVAL_DYNAMICS) hands a formulation M' and Q'
 * (Eq. 12): M' is N x N and dense for a chain, so forming it costs N^2 and a
 * product M' zdd as much again. A formulation whose rows are M' zdd - Q'
 * (open-loop) may ask the host for the rows themselves instead: the host
 * sums each body's Mbar_j times its acceleration from zdd, less its
 * Qbar_j - Mbar_j Zdot0_j, over subtrees and projects them on the joints
 * (the Newton-Euler recursion in the semirecursive form), N times a few
 * hundred operations, without M'.
 *
 * An optional service (get_service(host, MH_SERVICE_INVERSE_DYNAMICS)): a
 * host without it returns NULL, and the formulation forms M' zdd - Q' from
 * evaluate_mechanics as before. */
#ifndef MONOHYDRA_INVERSE_DYNAMICS_H
#define MONOHYDRA_INVERSE_DYNAMICS_H

#include "monohydra/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Formulations, from start on (as evaluate_mechanics). */
#define MH_SERVICE_INVERSE_DYNAMICS "monohydra.inverse_dynamics/1"
typedef struct mh_inverse_dynamics_service {
  uint32_t struct_size;
  /* r = M'(z) zdd - Q'(z, zd) (Eq. 12) at request->t, z, zd, with every
   * subsystem force in Q' as under MH_EVAL_DYNAMICS; request->flags may add
   * MH_EVAL_SUBSYSTEMS (this is the Newton iterate's evaluation, whose
   * subsystem rows the host records) and nothing else: MH_EVAL_DYNAMICS is
   * implied, MH_EVAL_CONSTRAINTS refused (logged, MH_ERROR). zdd and r: N
   * entries each, r written. After it, evaluate_mechanics's last M' and Q'
   * are no longer valid. Returns what the subsystems' evaluation returned. */
  mh_status (*inverse_dynamics)(const struct mh_host* host, const mh_mech_request* request,
                                const double* zdd, double* r);
} mh_inverse_dynamics_service;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_INVERSE_DYNAMICS_H */
