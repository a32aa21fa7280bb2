/* monohydra SDK: how a component looks, for a host that draws the run (the
 * report's 3D view).
 *
 * A component knows what it is (an actuator with a barrel and a rod, a
 * spring between two points) and which of its states say how loaded it is (a
 * chamber's pressure); the host knows neither from the component's id. So a
 * component declares its look here, during setup, in terms of its own points
 * (add_point) and the global indices of states (add_state, add_port,
 * find_state), and a host draws it without knowing the component.
 *
 * An optional service (get_service(host, MH_SERVICE_VISUAL)): a host that
 * draws nothing returns NULL, and the component declares nothing. Declaring
 * nothing is fine: a host draws a component with points as a thin line
 * between them. Not part of monohydra.h: a component that is never drawn
 * needs none of it. */
#ifndef MONOHYDRA_VISUAL_H
#define MONOHYDRA_VISUAL_H

#include "monohydra/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a visual is (mh_visual_spec.kind). */
#define MH_VISUAL_ACTUATOR                                                 \
  1u /* a linear actuator between point_a and point_b: a barrel of length  \
        barrel_length from point_a toward point_b, a rod from point_b back \
        toward point_a; the stroke shows as the rod sliding in the barrel. \
        state_a colours the barrel's end at point_a (the cap chamber),     \
        state_b the end toward the rod (the rod chamber) */
#define MH_VISUAL_LINK                                                      \
  2u /* a straight element between point_a and point_b (a spring, a damper, \
        a rope) of diameter rod_diameter; barrel_length and barrel_diameter \
        unused; state_a colours it */

typedef struct mh_visual_spec {
  uint32_t struct_size;   /* sizeof(mh_visual_spec) */
  uint32_t kind;          /* MH_VISUAL_* */
  int32_t point_a;        /* this instance's point (add_point's index) */
  int32_t point_b;        /* another of its points */
  double barrel_length;   /* m, > 0 for an actuator */
  double barrel_diameter; /* m, > 0 for an actuator */
  double rod_diameter;    /* m, > 0 */
  int32_t state_a;        /* a global state index (e.g. a port's node pressure) whose */
  int32_t state_b;        /* value colours the part at a / b on the host's scale for
                             the state's unit; -1 for none */
} mh_visual_spec;

/* Subsystems, during setup. */
#define MH_SERVICE_VISUAL "monohydra.visual/1"
typedef struct mh_visual_service {
  uint32_t struct_size;
  /* Declares one visual of this instance (an instance may declare several).
   * A bad spec (unknown kind, a point not added, a size not positive and
   * finite, a state out of range) is logged and yields MH_ERROR. */
  mh_status (*add_visual)(const struct mh_host* host, const mh_visual_spec* spec);
} mh_visual_service;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_VISUAL_H */
