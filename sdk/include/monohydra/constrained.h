/* monohydra SDK: what a formulation says of its converged step to a host
 * that differentiates the step (forward sensitivities,
 * docs/identification.md). Optional: a host that does not know the id never
 * asks, and a formulation that does not answer it is differentiated with
 * its rows as they are. */
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

#endif /* MONOHYDRA_CONSTRAINED_H */
