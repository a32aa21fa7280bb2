/* monohydra SDK: which entries of a subsystem's jacobian can be non-zero,
 * and which entries of the mechanical block a formulation's need compute.
 *
 * Without a declaration the host takes an instance's rows to depend on every
 * state it touches: a dense block of n x n in the shared tangent (n =
 * num_touched). That is right for a valve, but a hose of N segments touches
 * 2N + 1 states and couples each only to its neighbours; its dense block
 * makes the sparse factorization cost N^3 a step where N would do. So an
 * instance may declare, during setup, the entries its contributions can make
 * non-zero; every other entry of its block is then zero at every state and
 * time. The host stops the run when the instance's first jacobian writes a
 * non-zero entry outside the declaration (naming the instance, the row and
 * the column); after it the host clears and reads the declared entries only,
 * so that a block costs its entries, not n^2 (an op that keeps to its
 * declaration still finds the whole block zero on entry). An entry left out
 * whose derivative is not zero (forward differences, or an op that omits it
 * too) makes the tangent wrong, not the results: Newton converges more
 * slowly or not at all, and `monohydra check` fails its tangent check.
 *
 * An optional service (get_service(host, MH_SERVICE_SPARSITY)): a host
 * without it returns NULL, and the instance's block stays dense. */
#ifndef MONOHYDRA_SPARSITY_H
#define MONOHYDRA_SPARSITY_H

#include "monohydra/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Subsystems, during setup, after the states concerned are touched (add_state,
 * add_port, find_state). */
#define MH_SERVICE_SPARSITY "monohydra.sparsity/1"
typedef struct mh_sparsity_service {
  uint32_t struct_size;
  /* Declares that this instance's contribution to the row of state rows[i]
   * may depend on state columns[i] (its value or its rate), for i < count;
   * global state indices, both touched by this instance. May be called
   * several times: the block is the union (the diagonal of every touched
   * state is always in it). An index out of range or not touched is logged
   * and yields MH_ERROR. */
  mh_status (*declare_entries)(const struct mh_host* host, uint32_t count, const int32_t* rows,
                               const int32_t* columns);
} mh_sparsity_service;

/* Formulations whose unknowns are the joint coordinates
 * (MH_EXT_COORDINATE_UNKNOWNS), from their first residual on: the entries of
 * the N x N mechanical block that can be non-zero, the same for M' (the
 * mechanism's mass matrix), K, C (mech_derivatives) and the tangent's
 * dr_dx, dr_dxd, dr_dxdd. In a tree they are the ancestor pairs, and the
 * pairs that subsystems with points or cut joints couple: O(N) for a tree
 * of bounded depth, where the dense blocks hold N^2. M', K and C are zero
 * at every other entry, and the host clears and reads the tangent's blocks
 * on these entries only, so a formulation may compute and copy on them
 * alone. Compressed columns: column c's rows are
 * row_index[column_start[c] .. column_start[c + 1]), ascending, with
 * num_columns = N; the arrays stay valid and unchanged for the instance's
 * life. */
#define MH_SERVICE_MECHANICAL_PATTERN "monohydra.mechanical_pattern/1"
typedef struct mh_mechanical_pattern_service {
  uint32_t struct_size;
  /* MH_ERROR (logged) for a formulation without coordinate unknowns, or
   * called during setup (the pattern is built after it). */
  mh_status (*mechanical_pattern)(const struct mh_host* host, uint32_t* num_columns,
                                  const int32_t** column_start, const int32_t** row_index);
} mh_mechanical_pattern_service;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_SPARSITY_H */
