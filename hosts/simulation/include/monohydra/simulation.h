/* monohydra's embedding API: a run of the engine as an object another
 * program drives, one step at a time: open a model, read any value between
 * two steps, save the whole state of the run and put it back (in this
 * process or, as bytes, in another), write the rows `monohydra run` writes.
 * docs/embedding.md shows a whole program.
 *
 * The rules, as FMI 3.0's C API keeps them:
 * - Every call returns a status (MHS_OK ... MHS_FATAL) and never throws,
 *   aborts or exits; mhs_message() says why the last call that did not
 *   return MHS_OK did not (kept through later calls that do, until the next
 *   that does not, or a restore).
 * - Every array travels with its length; strings are UTF-8, NUL-terminated,
 *   owned by the library and valid until the next call on the same handle.
 * - Instances are independent: several may run at once, in several threads,
 *   each used by one thread at a time: a call while another thread is in a
 *   call on the same instance is refused (MHS_ERROR; that thread's
 *   mhs_message says so) and changes nothing. mhs_cancel is the exception:
 *   any thread, or a signal handler, may call it. Opening a model is
 *   serialized inside the library (its plugins are loaded once per process).
 * - Units are SI, as the model's components declare them.
 *
 * Versioning is the SDK's: within one major version the API only grows
 * (functions and enum values appended, structs grown at their end behind
 * their struct_size), so a program built against 1.0 runs on every 1.x. */
#ifndef MONOHYDRA_SIMULATION_H
#define MONOHYDRA_SIMULATION_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MHS_API_VERSION_MAJOR 1u
#define MHS_API_VERSION_MINOR                                                    \
  5u /* 1.1: mhs_linearize; 1.2: mhs_set_parameter;                              \
      1.3: mhs_track_sensitivities, mhs_get_sensitivities; 1.4: mhs_estimator_*; \
      1.5: mhs_batch_* */

#if defined(__GNUC__) || defined(__clang__)
#define MHS_API __attribute__((visibility("default")))
#else
#define MHS_API
#endif

/* What a call did. */
typedef int32_t mhs_status;
enum {
  MHS_OK = 0,      /* done */
  MHS_WARNING = 1, /* done, and a plugin warned: mhs_message() has its words */
  MHS_DISCARD = 2, /* (1.5) done in part: an advance that mhs_cancel ended between two
                      steps (the run is at that accepted state and goes on from it);
                      a batch's call that stepped its other runs while some are
                      stopped (mhs_batch_run_status says which) */
  MHS_ERROR = 3,   /* not done: a bad argument (nothing changed) or a failed step
                      (the run keeps its last accepted state and takes no step
                      until a snapshot is restored) */
  MHS_FATAL = 4    /* the instance cannot go on (out of memory, a model that did not
                      open): only mhs_message and mhs_free remain */
};

typedef struct mhs_simulation mhs_simulation; /* one run */
typedef struct mhs_snapshot mhs_snapshot;     /* the whole state of a run between two steps */

/* (major << 16) | minor of the library loaded: compare with MHS_API_VERSION_*. */
MHS_API uint32_t mhs_api_version(void);

/* A value chosen over the model file's, by its path in the model as
 * `monohydra sweep` addresses it (docs/sweeps.md): "subsystems/valve/flow_coefficient",
 * "bodies/body1/mass", "formulation/alpha". Four paths choose as the command
 * line's flags do: "formulation", "integrator" (an id), "dt" and "t_end" (s). */
typedef struct mhs_setting {
  const char* path;
  const char* value; /* as the model file would write it */
} mhs_setting;

/* Opens the model file at `model_path` with `count` settings over it, loads
 * its plugins (the model's plugins: and plugin_paths, $MONOHYDRA_PLUGIN_PATH,
 * then the plugins installed beside this library) and sets every instance
 * up. `*out` receives a handle whenever `out` is not NULL, also when the
 * model did not open (status MHS_FATAL): its mhs_message() says why (file,
 * line, field, what was expected); free it with mhs_free either way.
 * MHS_WARNING (1.5): opened, and plugins warned while setting up. */
MHS_API mhs_status mhs_open_file(const char* model_path, const mhs_setting* settings, size_t count,
                                 mhs_simulation** out);
/* The same from the model's text: `label` names it in messages, `base_dir`
 * resolves its relative paths (NULL: the working directory). */
MHS_API mhs_status mhs_open_text(const char* yaml_text, const char* label, const char* base_dir,
                                 const mhs_setting* settings, size_t count, mhs_simulation** out);
/* Destroys the run and every plugin instance of it. NULL is ignored. */
MHS_API void mhs_free(mhs_simulation* sim);

/* What the last call on `sim` that did not return MHS_OK said, kept until
 * the next such call or a restore ("" when there was none). Valid until
 * the next call on `sim`; for a NULL handle, a text saying so; on a thread
 * refused because another was in a call on `sim`, that refusal. */
MHS_API const char* mhs_message(const mhs_simulation* sim);
/* (1.5) Ends the call in flight on `sim` at the next look between two steps
 * (mhs_advance returns MHS_DISCARD: the run is at an accepted state and goes
 * on from it), or, with no such call in flight, the next one at its start.
 * Any thread may call it, and a signal handler (it only sets a flag). */
MHS_API void mhs_cancel(mhs_simulation* sim);

/* The consistent state at t = 0 (the paper's initial conditions). The first
 * mhs_step, mhs_advance or mhs_restore starts the run when this was not called. */
MHS_API mhs_status mhs_start(mhs_simulation* sim);
/* One step of the model's dt. */
MHS_API mhs_status mhs_step(mhs_simulation* sim);
/* Steps until the run's time reaches `t` (s, within a millionth of a step):
 * a time before the current one is refused; the model's t_end is no limit. */
MHS_API mhs_status mhs_advance(mhs_simulation* sim, double t);
/* The time (s) and the number of steps of the last accepted state, and the
 * model's dt and t_end (s). Any pointer may be NULL. */
MHS_API mhs_status mhs_time(const mhs_simulation* sim, double* t, int64_t* steps, double* dt,
                            double* t_end);

/* What a value is. */
typedef int32_t mhs_kind;
enum {
  MHS_COORDINATE = 0,      /* a joint coordinate z_i (rad or m) */
  MHS_COORDINATE_RATE = 1, /* its rate zd_i (rad/s or m/s) */
  MHS_STATE = 2,           /* a component's state (a pressure, a spool position) */
  MHS_OUTPUT = 3,          /* a component's or the formulation's output (a stroke, a force) */
  MHS_INPUT = 4            /* one of the model's inputs (inputs:): set with mhs_set */
};

typedef struct mhs_variable_info {
  uint32_t struct_size; /* set by the caller to sizeof(mhs_variable_info) */
  mhs_kind kind;
  const char* name;      /* "z1", "z1_dot", a CSV column ("p1"), else "instance.state" */
  const char* qualified; /* "instance.state", "formulation.output", a node's name, "z1" */
  const char* unit;      /* SI, as declared ("" when none) */
  double min, max;       /* the declared range (min > max: none declared) */
} mhs_variable_info;

/* Values are numbered 0 .. count-1: coordinates, their rates, the states,
 * the outputs, then the inputs; the numbers are fixed once the model is open. */
MHS_API mhs_status mhs_variable_count(const mhs_simulation* sim, uint32_t* count);
MHS_API mhs_status mhs_variable(const mhs_simulation* sim, uint32_t index, mhs_variable_info* info);
/* The number of the value called `name` (its name or its qualified name). */
MHS_API mhs_status mhs_find(const mhs_simulation* sim, const char* name, uint32_t* index);
/* The values numbered `indices[0..count-1]` at the last accepted state. */
MHS_API mhs_status mhs_get(const mhs_simulation* sim, const uint32_t* indices, size_t count,
                           double* values);

/* Sets inputs (values numbered `indices`, each an MHS_INPUT) from the run's
 * time on, in place of their tables: before mhs_start, from t = 0; after, a
 * value that changes an input is a jump at the current time (the next step
 * starts from the rates at its right limit, as after a time event of a
 * table). All or nothing: a value that is not finite, not an input, or
 * outside a range its input refuses to leave (out_of_range: refuse) sets
 * none (MHS_ERROR); a value its input clamps is clamped (MHS_WARNING, the
 * message names it). */
MHS_API mhs_status mhs_set(mhs_simulation* sim, const uint32_t* indices, size_t count,
                           const double* values);

/* (1.2) Changes a value of the model in place, before mhs_start or between
 * two steps, without opening the model again: a body's mass, centre of mass
 * or inertia, or gravity, by its path as settings address it
 * ("bodies/body3/mass", "bodies/body3/com/0", "gravity/1"), in the units the
 * model file declares. The model file's parser checks the value and derives
 * from it what it derives when opening (the inertia of a shape from its
 * mass). The run goes on from its accepted state as a run of the changed
 * model; the energy balance's references move by the change's own jump.
 * A component's option too, when the component changes it in place
 * ("subsystems/valve/flow_coefficient": monohydra/parameters.h of the SDK),
 * in SI as component options are. Before mhs_start (or the first mhs_step),
 * a body's initial coordinate and rate ("bodies/crank/z0", ".../zd0"), the
 * loops closed again around them as when the model is opened.
 * MHS_ERROR and nothing changed: a path the model does not have, one that is
 * not such a value (an option its component reads only when it is set up:
 * open the model with the setting), a value the file's parser or the
 * component refuses (its range, named). */
MHS_API mhs_status mhs_set_parameter(mhs_simulation* sim, const char* path, double value);

/* 1.3: forward sensitivities (docs/identification.md). Before mhs_start (or
 * the first mhs_step): from then on every accepted step also carries the
 * derivatives of the run's values with respect to the `count` parameters at
 * `paths`, named as mhs_set_parameter names them ("bodies/body3/mass",
 * "subsystems/valve/flow_coefficient", "subsystems/pump/pressure"), each in
 * the model file's units. A call replaces the parameters of an earlier one.
 * MHS_ERROR, nothing tracked: after the run started, a path that is not
 * such a parameter (named), a run that cannot carry them (an explicit
 * integrator, solver.newton: articulated, a component that keeps state of
 * its own), count 0 or paths NULL. */
MHS_API mhs_status mhs_track_sensitivities(mhs_simulation* sim, const char* const* paths,
                                           size_t count);
/* At the accepted state: d(value indices[i]) / d(parameter j) into
 * out[i * k + j], k the number of parameters tracked (row-major). NaN for a
 * value without one (an input, an output its formulation does not
 * differentiate). MHS_ERROR: none tracked, an index out of range (named),
 * out NULL. */
MHS_API mhs_status mhs_get_sensitivities(const mhs_simulation* sim, const uint32_t* indices,
                                         size_t count, double* out);

/* The rows `monohydra run` writes for this model (its output: columns and
 * interval; every column at every step when it has none). */
MHS_API mhs_status mhs_row_size(const mhs_simulation* sim, uint32_t* columns);
MHS_API mhs_status mhs_row_name(const mhs_simulation* sim, uint32_t column, const char** name);
/* Whether the last accepted step is one the run writes a row at (t = 0 and
 * every output interval). */
MHS_API mhs_status mhs_row_due(const mhs_simulation* sim, int32_t* due);
/* The row at the last accepted state, as numbers (`capacity` at least the
 * row's size) or as the CSV text `monohydra run` writes, newline included,
 * NUL-terminated (header != 0: the header line). `*length` receives the
 * text's length without the NUL, also when `capacity` is too small (then
 * MHS_ERROR and nothing written). */
MHS_API mhs_status mhs_row(const mhs_simulation* sim, double* values, size_t capacity);
MHS_API mhs_status mhs_row_text(const mhs_simulation* sim, int32_t header, char* text,
                                size_t capacity, size_t* length);

/* Snapshots: the whole state of a run between two steps (every unknown,
 * every plugin's own state, the energy balance, the work counters). A run
 * restored from one goes on as the run it was saved from went on, to the
 * bit. A snapshot restores into any run opened from the same model with the
 * same settings, in this process or (as bytes) in another of the same build. */
MHS_API mhs_status mhs_snapshot_new(mhs_simulation* sim, mhs_snapshot** out);
MHS_API void mhs_snapshot_free(mhs_snapshot* snapshot);
/* Saves the run's state into `snapshot` (its storage reused: saving again
 * into the same snapshot allocates nothing for the host's part). */
MHS_API mhs_status mhs_save(mhs_simulation* sim, mhs_snapshot* snapshot);
/* Puts a saved state back: all of it or, when refused (another model or
 * settings, damaged bytes), nothing. A run whose step failed steps again.
 * (1.5) MHS_WARNING when a value changed in place (a body's mass, centre of
 * mass or inertia, gravity) differs from what it was at the save: the state
 * is restored and goes on as the run's model now is; the message names each
 * value with both. */
MHS_API mhs_status mhs_restore(mhs_simulation* sim, const mhs_snapshot* snapshot);
/* The snapshot as bytes (owned by the snapshot, valid until it changes) and
 * a snapshot read back from such bytes; messages go to `sim`. */
MHS_API mhs_status mhs_snapshot_bytes(mhs_simulation* sim, mhs_snapshot* snapshot,
                                      const void** bytes, size_t* size);
MHS_API mhs_status mhs_snapshot_read(mhs_simulation* sim, mhs_snapshot* snapshot, const void* bytes,
                                     size_t size);

/* Linearisation, for control design: the state-space matrices of the run
 * about its last accepted state,
 *   dX/dt = A X + B u,   Y = C X + D u,
 * over the model's inputs u (MHS_INPUT values, in file order) and the
 * outputs Y numbered `outputs[0..count-1]` (coordinates, their rates,
 * states, outputs: not inputs). X are the run's own states (the
 * formulation's positions and velocities, the components' non-algebraic
 * states), named by mhs_linearization_name. The run is left as it was: its
 * next steps are those it would have taken, to the bit. Refused (MHS_ERROR)
 * before mhs_start, after a failed step, with an explicit integrator, for
 * an unknown index or an input as an output. docs/embedding.md gives the
 * method and what its eigenvalues mean. */
typedef struct mhs_linearization mhs_linearization;
MHS_API mhs_status mhs_linearize(mhs_simulation* sim, const uint32_t* outputs, size_t count,
                                 mhs_linearization** out);
MHS_API void mhs_linearization_free(mhs_linearization* lin);
/* n states, m inputs, p outputs, and the time t (s) it was taken at. Any
 * pointer may be NULL. Messages of these calls go to `sim`. */
MHS_API mhs_status mhs_linearization_size(mhs_simulation* sim, const mhs_linearization* lin,
                                          uint32_t* n, uint32_t* m, uint32_t* p, double* t);
/* Matrix `which` ('A' n x n, 'B' n x m, 'C' p x n, 'D' p x m) column-major
 * into `values` (`capacity` at least its rows x columns). */
MHS_API mhs_status mhs_linearization_matrix(mhs_simulation* sim, const mhs_linearization* lin,
                                            char which, double* values, size_t capacity);
/* The name and SI unit of state, input or output `k` (valid as long as `lin`). */
typedef int32_t mhs_linear_role;
enum { MHS_LINEAR_STATE = 0, MHS_LINEAR_INPUT = 1, MHS_LINEAR_OUTPUT = 2 };
MHS_API mhs_status mhs_linearization_name(mhs_simulation* sim, const mhs_linearization* lin,
                                          mhs_linear_role role, uint32_t k, const char** name,
                                          const char** unit);

/* 1.4: state estimation (docs/estimation.md). An estimator is a Kalman
 * filter that drives the run it is made on: each mhs_estimator_update steps
 * the run (the filter's prediction) to the readings' time and corrects its
 * state with them, so that every value mhs_get reads is the estimate. Its
 * sensors are the model file's (sensors:), in their order. Messages of
 * these calls go to `sim`; an estimator is used with the run it was made
 * on only, and freed before it. */
typedef struct mhs_estimator mhs_estimator;
typedef struct mhs_estimator_options {
  uint32_t struct_size;      /* set by the caller to sizeof(mhs_estimator_options) */
  const char* filter;        /* "ekf" (also NULL: the extended filter) or "ukf" (unscented) */
  const char* const* params; /* estimated beside the state, by path as mhs_set_parameter
                                names them ("subsystems/valve/flow_coefficient") */
  size_t param_count;
  /* The noise of states (by their names, mhs_estimator_name) and of the
   * parameters (by their paths) where the defaults will not do: the
   * standard deviation its error gains in a second and that of its initial
   * error; NaN keeps that default (docs/estimation.md). */
  const char* const* noise_names;
  const double* plant_sd;
  const double* initial_sd;
  size_t noise_count;
} mhs_estimator_options;

/* Starts the run if it has not, and sets the filter up at its state.
 * MHS_ERROR, nothing made: a model without sensors or with one the filter
 * cannot take (a delay, a noise not above 0), an unknown filter, a path
 * that is not a parameter, a noise name that is neither, a negative or
 * non-finite standard deviation, a run whose last step failed. */
MHS_API mhs_status mhs_estimator_new(mhs_simulation* sim, const mhs_estimator_options* options,
                                     mhs_estimator** out);
MHS_API void mhs_estimator_free(mhs_estimator* est);
/* The filter's states (the run's states X, then the parameters) and its sensors. */
MHS_API mhs_status mhs_estimator_size(mhs_simulation* sim, const mhs_estimator* est,
                                      uint32_t* states, uint32_t* sensors);
typedef int32_t mhs_estimator_role;
enum { MHS_ESTIMATOR_STATE = 0, MHS_ESTIMATOR_SENSOR = 1 };
/* The name and SI unit of state or sensor `k` (a parameter's unit is "":
 * its path's, as the model file writes it). Valid as long as `est`. */
MHS_API mhs_status mhs_estimator_name(mhs_simulation* sim, const mhs_estimator* est,
                                      mhs_estimator_role role, uint32_t k, const char** name,
                                      const char** unit);
/* The readings taken at time `t` (s), one per sensor (`count` the
 * sensors'), NaN for a sensor without a sample: the run is stepped to the
 * step nearest `t` (none if it is there), then corrected. A second update
 * on the same step corrects again (sequential updates). MHS_ERROR: `t`
 * before the run's step, a wrong count, an infinite reading; the filter
 * stopped (it diverged: the sensor furthest off named; a correction that
 * cannot be put into the run; a failed step, which stops the run too): it
 * takes no update after that. */
MHS_API mhs_status mhs_estimator_update(mhs_simulation* sim, mhs_estimator* est, double t,
                                        const double* readings, size_t count);
/* The estimate (`x`, n values) and its covariance (`covariance`, n x n,
 * column-major; NULL: not wanted), n the filter's states. */
MHS_API mhs_status mhs_estimator_state(mhs_simulation* sim, const mhs_estimator* est, double* x,
                                       double* covariance, size_t n);
/* Of the last update, per sensor (NaN without a sample): the innovation
 * (reading - model's reading - bias) and its standard deviation; `nis` its
 * normalised square (NaN: no sample). Any pointer may be NULL. */
MHS_API mhs_status mhs_estimator_innovations(mhs_simulation* sim, const mhs_estimator* est,
                                             double* innovation, double* sd, size_t count,
                                             double* nis);

/* 1.5: a batch, many runs of one model stepped together (docs/batches.md).
 * The model is read, its plugins loaded and its value table made once for
 * every run; each run has its own state, its own parameters (by path, as
 * mhs_set_parameter takes them) and its own inputs. Its calls step every run
 * in parallel on the batch's threads; each run's result is, to the bit, the
 * one it would have stepped alone (an mhs_simulation of the same model with
 * the same parameters and inputs). A run whose step fails stops alone: it
 * keeps its last accepted state and its reason (mhs_batch_run_status) and
 * takes no step until mhs_batch_restore; the others go on. A batch is used
 * by one thread at a time, as a run is. */
typedef struct mhs_batch mhs_batch;
typedef struct mhs_batch_snapshot mhs_batch_snapshot; /* every run's state */
/* `runs` runs (at least 1) of the model at `model_path` with `count`
 * settings over it, stepped on `threads` threads in all (0: one per core).
 * As mhs_open_file: `*out` receives a handle also when the model did not
 * open (MHS_FATAL, mhs_batch_message says why); free it with mhs_batch_free.
 * MHS_WARNING: opened, and plugins warned while setting the runs up. */
MHS_API mhs_status mhs_batch_open_file(const char* model_path, const mhs_setting* settings,
                                       size_t count, uint32_t runs, uint32_t threads,
                                       mhs_batch** out);
MHS_API mhs_status mhs_batch_open_text(const char* yaml_text, const char* label,
                                       const char* base_dir, const mhs_setting* settings,
                                       size_t count, uint32_t runs, uint32_t threads,
                                       mhs_batch** out);
MHS_API void mhs_batch_free(mhs_batch* batch);
/* What the last call on `batch` that did not return MHS_OK said, kept until
 * the next such call or a restore, as mhs_message; a call that stopped runs
 * names each ("run 3: t = ... s, step ...: ..."); on a thread refused
 * because another was in a call on `batch`, that refusal. */
MHS_API const char* mhs_batch_message(const mhs_batch* batch);
/* Ends the mhs_batch_step or mhs_batch_advance in flight on `batch`: each
 * run stops at its next look between two of its steps, at an accepted state,
 * and the call returns MHS_DISCARD (the runs go on from there; their times
 * may differ). With no such call in flight, the next one ends at its start.
 * Any thread may call it, and a signal handler (it only sets a flag). */
MHS_API void mhs_batch_cancel(mhs_batch* batch);
/* The number of runs and of threads. Either pointer may be NULL. */
MHS_API mhs_status mhs_batch_size(const mhs_batch* batch, uint32_t* runs, uint32_t* threads);
/* The model's dt and t_end (s), the same for every run. Either may be NULL. */
MHS_API mhs_status mhs_batch_time(const mhs_batch* batch, double* dt, double* t_end);
/* A value of run `run`'s model changed in place, as mhs_set_parameter. */
MHS_API mhs_status mhs_batch_set_parameter(mhs_batch* batch, uint32_t run, const char* path,
                                           double value);
/* Starts every run not started (the first step or advance does it too). */
MHS_API mhs_status mhs_batch_start(mhs_batch* batch);
/* Every run that has not stopped takes `steps` steps, or steps until its
 * time reaches `t` (s). MHS_OK: every run did; MHS_DISCARD: some runs are
 * stopped (now or before), the message names each, the others went on;
 * MHS_ERROR: a bad argument, no run stepped. */
MHS_API mhs_status mhs_batch_step(mhs_batch* batch, uint64_t steps);
MHS_API mhs_status mhs_batch_advance(mhs_batch* batch, double t);
/* The values are numbered as mhs_variable numbers a run's. */
MHS_API mhs_status mhs_batch_variable_count(const mhs_batch* batch, uint32_t* count);
MHS_API mhs_status mhs_batch_variable(const mhs_batch* batch, uint32_t index,
                                      mhs_variable_info* info);
MHS_API mhs_status mhs_batch_find(const mhs_batch* batch, const char* name, uint32_t* index);
/* Value `index` of every run, one per run in run order (`runs` the batch's). */
MHS_API mhs_status mhs_batch_get(const mhs_batch* batch, uint32_t index, double* values,
                                 size_t runs);
/* Input `index` of every run from values[run], as mhs_set: all or nothing
 * (MHS_ERROR names the run refused), MHS_WARNING naming the runs clamped. */
MHS_API mhs_status mhs_batch_set(mhs_batch* batch, uint32_t index, const double* values,
                                 size_t runs);
/* Run `run`: MHS_OK, or MHS_ERROR when it is stopped, with its reason in
 * `*message` (valid until the next call on `batch`); its time (s) and
 * steps. Any pointer but `status` may be NULL. */
MHS_API mhs_status mhs_batch_run_status(const mhs_batch* batch, uint32_t run, mhs_status* status,
                                        double* t, int64_t* steps, const char** message);
/* Every run's whole state: saved, and put back (each run's stop forgotten,
 * and MHS_WARNING naming the runs whose model values differ, as
 * mhs_restore). A snapshot fits the batch it was made for. */
MHS_API mhs_status mhs_batch_snapshot_new(mhs_batch* batch, mhs_batch_snapshot** out);
MHS_API void mhs_batch_snapshot_free(mhs_batch_snapshot* snapshot);
MHS_API mhs_status mhs_batch_save(mhs_batch* batch, mhs_batch_snapshot* snapshot);
MHS_API mhs_status mhs_batch_restore(mhs_batch* batch, const mhs_batch_snapshot* snapshot);
/* A batch's snapshot as bytes (each run's as mhs_snapshot_bytes writes it,
 * after the run count; owned by the snapshot, valid until it changes), and
 * a snapshot read back from such bytes, for a batch of as many runs of the
 * same model, in this process or another of the same build. */
MHS_API mhs_status mhs_batch_snapshot_bytes(mhs_batch* batch, mhs_batch_snapshot* snapshot,
                                            const void** bytes, size_t* size);
MHS_API mhs_status mhs_batch_snapshot_read(mhs_batch* batch, mhs_batch_snapshot* snapshot,
                                           const void* bytes, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_SIMULATION_H */
