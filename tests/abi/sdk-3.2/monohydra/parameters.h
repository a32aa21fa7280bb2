/* monohydra SDK (optional header): a component's options that are
 * parameters, changed in place. A host changes them between steps (a
 * payload picked up, a value being identified) and, to differentiate a
 * step, around single calls inside one (forward sensitivities,
 * docs/identification.md): each is one of the component's numeric options,
 * named by its key as the model file writes it, in SI units, with the
 * values it takes. A host that does not know the id never asks; a component
 * that does not answer it keeps its options as setup read them. */
#ifndef MONOHYDRA_PARAMETERS_H
#define MONOHYDRA_PARAMETERS_H

#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* get_extension(self, MH_EXT_PARAMETERS) returns a const
 * mh_parameters_extension*; every `instance` argument is the instance table
 * it came from (a const mh_subsystem*). */
#define MH_EXT_PARAMETERS "monohydra.parameters/1"

typedef struct mh_parameter_info {
  uint32_t struct_size; /* sizeof(mh_parameter_info) of the host's SDK */
  const char* key;      /* the option's key, as the model file writes it */
  const char* unit;     /* its SI unit, e.g. "Pa", "m^3/(s sqrt(Pa) V)" */
  double lower, upper;  /* the values it takes, both included (+-HUGE_VAL: no bound) */
} mh_parameter_info;

typedef struct mh_parameters_extension {
  uint32_t struct_size; /* sizeof(mh_parameters_extension) of the plugin's SDK */

  /* How many of its options are parameters: fixed from the end of setup. */
  uint32_t (*count)(const void* instance);

  /* Parameter `index` (< count) into *info (the strings live as long as the
   * instance). MH_ERROR for an index out of range. */
  mh_status (*info)(const void* instance, uint32_t index, mh_parameter_info* info);

  /* Its value now into *value. */
  mh_status (*get)(const void* instance, uint32_t index, double* value);

  /* Its value from the next call on (evaluate, jacobian, energy, ...), as if
   * setup had read it: whatever the component derives from it follows. Any
   * time after setup, between any two calls. A value outside [lower, upper]
   * or not finite: MH_ERROR with the reason logged, nothing changed. Not
   * state: a snapshot does not carry it (the host that set it sets it
   * again). */
  mh_status (*set)(const void* instance, uint32_t index, double value);
} mh_parameters_extension;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_PARAMETERS_H */
