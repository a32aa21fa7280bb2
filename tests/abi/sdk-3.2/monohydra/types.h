/* monohydra SDK: basic types, status codes and versions shared by every
 * interface. Plain C11; safe to include from C++.
 *
 * Versioning (docs/sdk.md), one rule: a plugin built against ABI major M loads
 * in any host of major M whatever the minors. A minor version only appends
 * fields at the end of structs, and every struct begins with struct_size (the
 * sizeof of its writer's SDK): a reader reads, and a writer writes, a struct
 * only up to the smaller of its own sizeof and that struct_size, so fields
 * past it are absent (zero, NULL: "not supported"). Optional services are
 * extensions by versioned string id. A published struct is never edited in
 * place: after 3.0 fields are only appended (CLAP's rule), never moved.
 *
 * ABI 3 is the break that made the contract one shape: column-major matrices
 * everywhere, every array with its length (mh_unknown_values and friends),
 * the same head on every instance table (setup, destroy, get_extension), the
 * same factory in every role (example_model included), the step's
 * coefficients at a formulation's begin_step, explicit integrators with
 * operations of their own, an instance's own state saved and loaded
 * (state.h) for snapshots of a run. A 2.x plugin is refused, naming both versions and
 * the migration section of docs/sdk.md ("Migrating a 2.x plugin").
 *
 * 3.1 appends the signals service (host.h, MH_SERVICE_SIGNALS): a command
 * option read as a signal, a time table or one of the model's inputs.
 * 3.2 appends option_signal_port to it: a signal that is a state of the run
 * (another instance's output: sensors and controllers wired by name). */
#ifndef MONOHYDRA_TYPES_H
#define MONOHYDRA_TYPES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MH_ABI_VERSION_MAJOR 3u
#define MH_ABI_VERSION_MINOR 2u
#define MH_ABI_VERSION_PATCH 0u

typedef struct mh_version {
  uint32_t major;
  uint32_t minor;
  uint32_t patch;
} mh_version;

#define MH_ABI_VERSION_INIT \
  { MH_ABI_VERSION_MAJOR, MH_ABI_VERSION_MINOR, MH_ABI_VERSION_PATCH }

/* Status of every call, with FMI 3.0's meanings. */
typedef enum mh_status {
  MH_OK = 0,      /* done */
  MH_WARNING = 1, /* done, but something was logged that the user should see */
  MH_DISCARD = 2, /* not done; state unchanged; the caller may retry, e.g. with a smaller step */
  MH_ERROR = 3,   /* not done; this instance is unusable; the reason was logged */
  MH_FATAL = 4    /* not done; no instance of this plugin can be trusted any more */
} mh_status;

typedef enum mh_log_level {
  MH_LOG_DEBUG = 0,
  MH_LOG_INFO = 1,
  MH_LOG_WARNING = 2,
  MH_LOG_ERROR = 3
} mh_log_level;

/* The kind of a Newton unknown: what the time integrator ties to it. */
typedef enum mh_unknown_kind {
  MH_UNKNOWN_SECOND_ORDER = 0, /* a position: has a rate xd and a second rate xdd */
  MH_UNKNOWN_FIRST_ORDER = 1,  /* a pressure, a spool position: has a rate xd */
  MH_UNKNOWN_ALGEBRAIC = 2     /* a multiplier, a source's flow: no rate */
} mh_unknown_kind;

/* What an output's value means, so hosts can show it without knowing the
 * component (mh_output_spec.kind). A host shows a kind it does not know (one
 * a later minor version added) as a signal. */
typedef enum mh_output_kind {
  MH_OUTPUT_SIGNAL = 0,     /* a quantity over time in `unit`: plotted, written to results */
  MH_OUTPUT_COORDINATE = 1, /* the 1-based index of a joint coordinate in use (e.g. an
                               independent coordinate): shown by the coordinate's name;
                               summaries give the first value and whether it changed */
  MH_OUTPUT_COUNTER = 2     /* a count of events so far (e.g. re-partitions): summaries
                               give the final value */
} mh_output_kind;

/* Describes one component (a formulation or a subsystem) without creating it. */
typedef struct mh_component_descriptor {
  uint32_t struct_size; /* sizeof(mh_component_descriptor) of the plugin's SDK */
  const char* id;       /* unique name used in model files, e.g. "spring-damper" */
  const char* name;     /* human readable */
  const char* vendor;
  const char* version; /* the component's own version, e.g. "1.0.0" */
  const char* description;
} mh_component_descriptor;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_TYPES_H */
