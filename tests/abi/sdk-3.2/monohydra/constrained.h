/* monohydra SDK: what a formulation says of its start and its converged
 * step to a host that differentiates a run (forward sensitivities,
 * docs/identification.md). Optional: a host that does not know an id never
 * asks, and a formulation that does not answer one is differentiated with
 * its rows as they are and its initial state as setup read it. */
#ifndef MONOHYDRA_CONSTRAINED_H
#define MONOHYDRA_CONSTRAINED_H

/* Formulation extension (get_extension with this id returns any non-NULL
 * pointer when it holds; with MH_EXT_COORDINATE_UNKNOWNS): a converged step
 * satisfies the cut-joint constraints Phi(z) = 0, the multipliers it
 * iterates between Newton updates (an augmented Lagrangian's, Eq. 19)
 * having made them hold, and its rows depend on those multipliers through
 * Phi_z^T alone. The host then solves the step's tangent bordered by Phi_z
 * instead of holding the multipliers fixed. */
#define MH_EXT_CONSTRAINED_AT_CONVERGENCE "monohydra.constrained-at-convergence/1"

/* Formulation extension (any non-NULL pointer when it holds): start reads
 * the host's assembled initial state (mech_info's z0 and zd0) at each call,
 * not a copy setup took, so that a host may move it between setup and start
 * (an initial coordinate as a parameter, differenced through start). What
 * setup chose from z0 (e.g. the independent coordinates) stays as it was. */
#define MH_EXT_INITIAL_STATE_AT_START "monohydra.initial-state-at-start/1"

#endif /* MONOHYDRA_CONSTRAINED_H */
