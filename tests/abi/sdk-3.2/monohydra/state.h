/* monohydra SDK: an instance's own state as bytes, so that a host can save a
 * run between two steps and restore it later, into the same instance or into
 * another one made from the same model (a snapshot: the embedding API's, a
 * controller's branch, an FMU's get/set state).
 *
 * The host keeps what it hands a plugin (the unknowns, their rates, the
 * subsystem states, the outputs); the extension carries the rest: what an
 * instance keeps from one step to the next (a formulation's accepted
 * coordinates and multipliers, a choice of independent coordinates, an
 * integrator's history). Scratch that the next step recomputes is not state.
 *
 * A formulation or an integrator, and a subsystem with an accept operation,
 * that offers no MH_EXT_STATE makes the host refuse to snapshot its run,
 * naming it. A subsystem without accept keeps nothing between steps (its
 * states are the host's) and needs no extension. */
#ifndef MONOHYDRA_STATE_H
#define MONOHYDRA_STATE_H

#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* get_extension(self, MH_EXT_STATE) returns a const mh_state_extension*.
 * Every `instance` argument is the instance table the extension came from
 * (a const mh_formulation*, mh_integrator* or mh_subsystem*). */
#define MH_EXT_STATE "monohydra.state/3"

typedef struct mh_state_extension {
  uint32_t struct_size; /* sizeof(mh_state_extension) of the plugin's SDK */

  /* The bytes the state takes: fixed from the end of setup until destroy, so
   * that a host sizes its snapshots once (0: nothing of its own). */
  uint64_t (*size)(const void* instance);

  /* Writes the state as the next step will read it into bytes[0, size).
   * Called between steps only (after start, an accept or a restart), never
   * during one; changes nothing in the instance. */
  mh_status (*save)(const void* instance, void* bytes, uint64_t size);

  /* Makes the instance's state the one `bytes` holds, as save wrote it for an
   * instance of the same component set up with the same options. A size that
   * is not the instance's, or bytes it cannot take (an index out of range):
   * MH_ERROR with the reason logged, the instance unchanged. The host then
   * goes on with the next step (an integrator's begin_step, a formulation's
   * begin_step) as it would have after the save. */
  mh_status (*load)(const void* instance, const void* bytes, uint64_t size);
} mh_state_extension;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_STATE_H */
