/* monohydra SDK: the services the host hands to every component instance.
 *
 * The host creates one mh_host per component instance, so every call below
 * speaks for that instance (its options, its log lines, its states). The
 * services are tables found by id (get_service), one per role's need. The table
 * and everything it points to stay valid until the instance is destroyed.
 * Calls are made from the thread that called the plugin; a host never calls one
 * instance from two threads at once. Strings and arrays the host returns are
 * owned by the host. Every array travels with its length, and every matrix
 * is column-major (a table of option values is a list of rows: not a matrix).
 *
 * Structs the plugin hands in (specs, results to fill) begin with struct_size
 * = sizeof of the plugin's SDK: the host reads and writes them only up to that
 * size (types.h). The host copies every string of a spec during the call. */
#ifndef MONOHYDRA_HOST_H
#define MONOHYDRA_HOST_H

#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What evaluate_mechanics computes (bit flags). */
#define MH_EVAL_DYNAMICS 0x1u    /* M' and Q' (Eq. 12), with every load applied */
#define MH_EVAL_CONSTRAINTS 0x2u /* Phi, Phi_z and Phi_z_dot * zd of the cut joints */
#define MH_EVAL_SUBSYSTEMS                                         \
  0x4u /* this is the Newton iterate's evaluation: the subsystems' \
          residual rows (and powers) are recorded as the step's */
#define MH_EVAL_POSITIONS_ONLY                                          \
  0x8u /* with MH_EVAL_CONSTRAINTS: Phi and Phi_z only, phi_dot_zd NULL \
        */
/* The subsystems' forces always enter Q' under MH_EVAL_DYNAMICS, evaluated at the
 * host's current subsystem states and rates. */

/* The mechanism, as the host hands it to a formulation once, at setup, after
 * every command-line override: nothing here changes during the run. */
typedef struct mh_mech_info {
  uint32_t struct_size;
  uint32_t num_coordinates;            /* N: relative joint coordinates, one per body */
  uint32_t num_constraints;            /* m: rows of Phi(z) = 0 from the cut joints */
  const char* const* coordinate_names; /* N names, e.g. "z1" */
  const uint8_t* coordinate_is_angle;  /* N flags: 1 revolute (rad), 0 prismatic (m) */
  double position_tolerance;           /* the model's Newton tolerance on coordinates (rad or m) */
  double t0;                           /* the initial time (s) */
  const double* z0;                    /* N: initial coordinates, assembled by the host so that
                                          Phi(z0) = 0 when there are cut joints */
  const double* zd0;                   /* N: initial rates, with Phi_z zd0 = 0 */
} mh_mech_info;

typedef struct mh_mech_request {
  uint32_t struct_size;
  uint32_t flags;   /* MH_EVAL_* */
  double t;         /* s */
  const double* z;  /* N */
  const double* zd; /* N */
} mh_mech_request;

/* Results, owned by the host, valid until the next evaluate_mechanics call. Matrices
 * are dense and column-major. Pointers for what was not requested are NULL. */
typedef struct mh_mech_result {
  uint32_t struct_size;
  const double* M;          /* N x N, M' */
  const double* Q;          /* N, Q' */
  const double* phi;        /* m, Phi */
  const double* phi_z;      /* m x N, Phi_z */
  const double* phi_dot_zd; /* m, Phi_z_dot * zd: the constraint accelerations are
                               Phi_z * zdd + phi_dot_zd = d^2 Phi / dt^2 */
} mh_mech_result;

/* Port roles (mh_port_spec.role). */
#define MH_PORT_FLOW                                                 \
  0u /* exchanges flow with the node and reads its effort: a valve's \
        port, a volume, a cylinder chamber */
#define MH_PORT_EFFORT                                            \
  1u /* imposes the node's effort: a pressure source. At most one \
        per node. */

/* A port of a subsystem instance: its connection to a node of a network (a
 * hydraulic node: effort = pressure). The model file joins ports into nodes by
 * name (subsystems/<name>/ports/<key>: NODE). The node's effort is one state of
 * the run, shared by every port on the node; its row is the node's balance, to
 * which every port adds what leaves the node through it (storage terms, such as
 * C dp/dt of a volume, count as leaving). */
typedef struct mh_port_spec {
  uint32_t struct_size; /* sizeof(mh_port_spec) */
  const char* key;      /* the port's name, e.g. "A" */
  const char* domain;   /* e.g. "hydraulic": every port on a node must agree */
  const char* unit;     /* of the effort, e.g. "Pa" */
  uint32_t role;        /* MH_PORT_FLOW or MH_PORT_EFFORT */
  double initial;       /* the node's initial effort, or NaN for no opinion; the
                           ports that give one must agree */
  double abs_tolerance; /* Newton increment tolerance on the effort, or NaN; the
                           node takes the smallest given */
} mh_port_spec;

/* Roles a component may give a state or an output (mh_state_spec.role,
 * mh_output_spec.role), so that hosts treat them without knowing the
 * component: NULL or "" for none. */
#define MH_ROLE_CONTROL_SIGNAL                                                \
  "control-signal" /* a control input's actual value (a valve spool): reports \
                      shade where |value| exceeds 1 % of max(|range_min|,     \
                      |range_max|) */
#define MH_ROLE_DISSIPATION_PART                                                   \
  "dissipation-part" /* an output (W) that is a share of its instance's dissipated \
                        power (the energy op's): its outputs with this role add up \
                        to it, and reports break the instance's dissipation down   \
                        by them */

/* A state of a subsystem instance (add_state). */
typedef struct mh_state_spec {
  uint32_t struct_size; /* sizeof(mh_state_spec) */
  const char* name;     /* e.g. "p" */
  const char* unit;     /* e.g. "Pa" */
  double initial;
  double abs_tolerance; /* on its Newton increment */
  const char* role;     /* MH_ROLE_* or NULL */
  double range_min;     /* the range it is meant to stay in (its role's scale); */
  double range_max;     /* both 0 for none */
} mh_state_spec;

/* An output of a component instance (add_output): a value it computes and the
 * host writes to the results beside the states. */
typedef struct mh_output_spec {
  uint32_t struct_size; /* sizeof(mh_output_spec) */
  const char* name;     /* e.g. "s"; unique within the instance */
  const char* unit;     /* e.g. "m"; "" for a count or an index */
  uint32_t kind;        /* mh_output_kind */
  const char* role;     /* MH_ROLE_* or NULL */
  double range_min;     /* as in mh_state_spec */
  double range_max;
} mh_output_spec;

/* A Newton unknown of a formulation (add_unknown). */
typedef struct mh_unknown_spec {
  uint32_t struct_size; /* sizeof(mh_unknown_spec) */
  const char* name;     /* e.g. "z3" or "lambda1": names it in failure messages */
  const char* unit;     /* e.g. "rad" */
  uint32_t kind;        /* mh_unknown_kind */
  double abs_tolerance; /* on its Newton increment, > 0 */
} mh_unknown_spec;

/* What mech_derivatives computes (bit flags). */
#define MH_DERIV_DYNAMICS 0x1u /* K and C of the dynamics */
#define MH_DERIV_CONSTRAINT_FORCES \
  0x2u /* d(Phi_z^T v)/dz for the request's v: the constraint forces' stiffness */
#define MH_DERIV_CONSTRAINT_ACCELERATIONS \
  0x4u /* dA/dz and dA/dzd of A = Phi_z zdd + Phi_z_dot zd */

/* A request for derivatives of the mechanics at (t, z, zd, zdd) */
typedef struct mh_mech_derivatives_request {
  uint32_t struct_size;
  uint32_t flags;    /* MH_DERIV_* */
  double t;          /* s */
  const double* z;   /* N */
  const double* zd;  /* N */
  const double* zdd; /* N (MH_DERIV_DYNAMICS, MH_DERIV_CONSTRAINT_ACCELERATIONS) */
  const double* v;   /* m (MH_DERIV_CONSTRAINT_FORCES), e.g. alpha Phi + lambda */
} mh_mech_derivatives_request;

/* Results, owned by the host, valid until the next call; dense, column-major;
 * NULL for what was not requested. */
typedef struct mh_mech_derivatives {
  uint32_t struct_size;
  const double* K;           /* N x N: d(M' zdd - Q')/dz, with every subsystem force at
                                the host's current states (their point-force derivatives
                                from point_force_jacobian, or differences) */
  const double* C;           /* N x N: d(M' zdd - Q')/dzd = -dQ'/dzd */
  const double* dPhizT_v_dz; /* N x N: d(Phi_z^T v)/dz */
  const double* dA_dz;       /* m x N */
  const double* dA_dzd;      /* m x N */
} mh_mech_derivatives;

/* The host's services, each a table of its own found by id with
 * mh_host.get_service, so that what an instance may call is what its role was
 * given: a service its role has no use for reads as NULL. Every function
 * takes the instance's mh_host first; tables live as long as the instance. A
 * later minor appends services (new ids) and fields (at the end of a table,
 * read up to its struct_size). */

struct mh_host;

/* Options of the instance from the model file (every role). */
#define MH_SERVICE_OPTIONS "monohydra.options/3"
typedef struct mh_options_service {
  uint32_t struct_size;
  /* The option `key`. With required = 0 a missing key yields `fallback` and
   * MH_OK. A present key of the wrong type, or a missing required one, is
   * reported by the host (file, line, field, what was expected) and yields
   * MH_ERROR. Keys that no call asked for are reported as unknown after
   * setup. Numbers are SI. */
  mh_status (*option_number)(const struct mh_host* host, const char* key, int required,
                             double fallback, double* out);
  mh_status (*option_string)(const struct mh_host* host, const char* key, int required,
                             const char* fallback, const char** out);
  /* A table of numbers with `columns` columns, row after row as the model file
   * lists them (e.g. a time signal: t, value per row); *rows receives the
   * number of rows, so data has rows x columns entries. */
  mh_status (*option_table)(const struct mh_host* host, const char* key, int required,
                            uint32_t columns, const double** data, uint32_t* rows);
  /* Reports an invalid option value with the file and line it came from.
   * Returns MH_ERROR so a plugin can write `return options->option_error(host,
   * "k", "> 0");`. */
  mh_status (*option_error)(const struct mh_host* host, const char* key, const char* expected);
} mh_options_service;

/* The mechanism (formulations; subsystems get mech_info alone, the other two
 * NULL). */
#define MH_SERVICE_MECHANISM "monohydra.mechanism/3"
typedef struct mh_mechanism_service {
  uint32_t struct_size;
  /* The mechanism's sizes, names and initial state. */
  mh_status (*mech_info)(const struct mh_host* host, mh_mech_info* out);
  /* Evaluates the core's semirecursive kinematics and dynamics at (t, z, zd),
   * from the formulation's setup on. Inside mh_formulation.residual the
   * formulation calls it with MH_EVAL_SUBSYSTEMS exactly once, at the
   * coordinates of the Newton iterate (which also fills the subsystem residual
   * rows); other calls (also during setup, e.g. to partition Phi_z(z0)) may
   * come as often as needed and leave the subsystems' rows untouched. */
  mh_status (*evaluate_mechanics)(const struct mh_host* host, const mh_mech_request* request,
                                  mh_mech_result* result);
  /* Analytic derivatives of the semirecursive dynamics and of the constraint
   * terms (computed recursively in the core, not by differences of the
   * dynamics), after the formulation's setup: e.g. the projections' W = M' +
   * C dxd_dx/dxdd_dx + K/dxdd_dx (Eqs. 20-21), or an analytic tangent.
   * Leaves the subsystems' rows and outputs untouched. */
  mh_status (*mech_derivatives)(const struct mh_host* host,
                                const mh_mech_derivatives_request* request,
                                mh_mech_derivatives* result);
} mh_mechanism_service;

/* Outputs (formulations and subsystems, during setup). */
#define MH_SERVICE_OUTPUTS "monohydra.outputs/3"
typedef struct mh_outputs_service {
  uint32_t struct_size;
  /* Declares an output of this instance. *index receives its index in the
   * run's output vector: a subsystem writes it in mh_subsystem_eval.outputs, a
   * formulation in mh_formulation.write_outputs. */
  mh_status (*add_output)(const struct mh_host* host, const mh_output_spec* spec, int32_t* index);
} mh_outputs_service;

/* A subsystem's place in the model: its states, ports, points and time
 * events (subsystems, during setup). */
#define MH_SERVICE_SUBSYSTEM_SETUP "monohydra.subsystem-setup/3"
typedef struct mh_subsystem_setup_service {
  uint32_t struct_size;
  /* Declares a state of this instance. *index receives its index in the global
   * state vector. States are first-order unknowns, or algebraic when no row
   * involves their rate (the host finds out at t0). */
  mh_status (*add_state)(const struct mh_host* host, const mh_state_spec* spec, int32_t* index);
  /* Finds another instance's state by its qualified name "instance.state", to
   * read it and add to its residual row. *index receives its global index. */
  mh_status (*find_state)(const struct mh_host* host, const char* qualified_name, int32_t* index);
  /* Attaches this instance to the body point the model file gives under
   * points/<key>. *index receives the point's local index 0, 1, ... */
  mh_status (*add_point)(const struct mh_host* host, const char* key, int32_t* index);
  /* Declares a port (see mh_port_spec). *index receives the global index of
   * its node's effort state: read it in y and ydot, add to its residual row. */
  mh_status (*add_port)(const struct mh_host* host, const mh_port_spec* spec, int32_t* index);
  /* The world position (m) of this instance's point `point` (from add_point)
   * at the initial, assembled configuration: e.g. a cylinder's initial length. */
  mh_status (*point_position)(const struct mh_host* host, int32_t point, double* position3);
  /* Declares a time (s) at which this instance's equations jump (a step of a
   * reference signal). When a step ends exactly there, the host evaluates the
   * step's end just before it (the left limit) and restarts the integrator just
   * after it (the right limit), which keeps the step's order. Evaluate signals
   * right-continuously: a table row at t_i holds from t_i. */
  mh_status (*add_time_event)(const struct mh_host* host, double t);
} mh_subsystem_setup_service;

/* A formulation's Newton unknowns (formulations, during setup). */
#define MH_SERVICE_UNKNOWNS "monohydra.unknowns/3"
typedef struct mh_unknowns_service {
  uint32_t struct_size;
  /* Declares the formulation's next Newton unknown (indices 0, 1, ... in call
   * order). The host's integrator ties its rates to it by its kind. */
  mh_status (*add_unknown)(const struct mh_host* host, const mh_unknown_spec* spec, int32_t* index);
} mh_unknowns_service;

/* A signal: a value the host keeps for a component (option_signal,
 * option_signal_port). The host writes *value before each call of the instance
 * that evaluates it (evaluate), with the signal's value at that call: a time
 * table's (linear between rows, right-continuous at a repeated time, every
 * such jump a time event, so a step ending at a jump is evaluated at its left
 * limit), an input's (held from the time it was set: a change between two
 * steps is a jump there), or, from option_signal_port (3.2), a state of the
 * run's (another instance's output port: a sensor's reading, a controller's
 * command). A signal of time or of an input is, within one call, a constant of
 * the unknowns, with no derivative to give; a state's is eval.y[state], and
 * the instance gives its derivatives in its jacobian. */
typedef struct mh_signal {
  uint32_t struct_size;
  const double* value; /* host-owned, valid as long as the instance */
  int32_t state;       /* -1: the signal depends on time alone (a table, an input);
                          >= 0 (option_signal_port only): the global index of the state
                          it reads, one of the states this instance touches */
} mh_signal;

/* Signals (subsystems, during setup; 3.1, option_signal_port 3.2). */
#define MH_SERVICE_SIGNALS "monohydra.signals/3"
typedef struct mh_signals_service {
  uint32_t struct_size;
  /* The option `key` as a signal: in the model file a table of rows [t (s),
   * value] (non-decreasing times, finite numbers) or the name of one of the
   * model's inputs (inputs:). A missing key with required = 0 yields the
   * constant `fallback`. A bad value is reported by the host (file, line,
   * field, what was expected) and yields MH_ERROR. `out->struct_size` is the
   * plugin's sizeof(mh_signal). A name of a state of the run is refused here
   * (the component would miss its derivative): see option_signal_port. */
  mh_status (*option_signal)(const struct mh_host* host, const char* key, int required,
                             double fallback, mh_signal* out);
  /* 3.2: the option `key` as a signal input port. As option_signal, and the
   * option may also name a state of the run, "instance.state" of an instance
   * above this one in the model file: the signal graph is joined by name, as
   * hydraulic nodes are. Then out->state receives the state's global index
   * and the state joins this instance's touched states, at this call's place
   * in their order (as find_state); *value holds eval.y[state] at each
   * evaluation, and the jacobian gives the derivatives in it. */
  mh_status (*option_signal_port)(const struct mh_host* host, const char* key, int required,
                                  double fallback, mh_signal* out);
} mh_signals_service;

typedef struct mh_host {
  uint32_t struct_size;   /* sizeof(mh_host) of the host's SDK: check before using
                             fields added by a later minor version */
  mh_version abi_version; /* the host's ABI version */
  void* host_data;        /* opaque: pass back unchanged */

  /* Logs a message for the user, any time. A plugin logs the reason before
   * returning MH_DISCARD, MH_ERROR or MH_FATAL. */
  void (*log)(const struct mh_host* host, mh_log_level level, const char* message);

  /* The service `id` (MH_SERVICE_*, or another host's "name/rev"), or NULL
   * when this instance's role has none of that id. A lookup by name: call it
   * at create or setup and keep the table, not in the time step. */
  const void* (*get_service)(const struct mh_host* host, const char* id);
} mh_host;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_HOST_H */
