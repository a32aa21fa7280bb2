/* point-load: a constant force, fixed in the world frame, acting at one body
 * point (a payload, a cable pulling steadily). Written in C11 against the
 * installed SDK only, as docs/plugin-guide.md walks through it. It has no
 * states and no outputs: setup only reads its option and attaches to a point. */
#include <stdlib.h>
#include <string.h>

#include "monohydra/monohydra.h"

typedef struct point_load {
  const mh_host* host;
  double force[3]; /* N, world frame */
  int32_t point;
} point_load;

static point_load* self(const mh_subsystem* s) {
  return (point_load*)s->plugin_data;
}

static mh_status setup(const mh_subsystem* s) {
  point_load* d = self(s);
  const mh_host* h = d->host;
  /* The services a subsystem's setup needs, found by id (host.h). */
  const mh_options_service* options =
      (const mh_options_service*)h->get_service(h, MH_SERVICE_OPTIONS);
  const mh_subsystem_setup_service* place =
      (const mh_subsystem_setup_service*)h->get_service(h, MH_SERVICE_SUBSYSTEM_SETUP);
  const double* f = NULL;
  uint32_t rows = 0;
  if (options == NULL || place == NULL) {
    h->log(h, MH_LOG_ERROR, "point-load: the host gives no options or subsystem-setup service");
    return MH_ERROR;
  }
  /* force: [Fx, Fy, Fz] is a table of one row and three columns. */
  if (options->option_table(h, "force", 1, 3, &f, &rows) != MH_OK) return MH_ERROR;
  if (rows != 1) return options->option_error(h, "force", "one vector [Fx, Fy, Fz] in N");
  memcpy(d->force, f, sizeof d->force);
  return place->add_point(h, "at", &d->point);
}

static mh_status evaluate(const mh_subsystem* s, const mh_subsystem_eval* eval) {
  const point_load* d = self(s);
  for (int i = 0; i < 3; ++i) eval->point_f[3 * d->point + i] += d->force[i];
  return MH_OK;
}

static void destroy(const mh_subsystem* s) {
  free(s->plugin_data);
  free((void*)s);
}

static const void* get_extension(const mh_subsystem* s, const char* id) {
  (void)s;
  (void)id;
  return NULL;
}

static const mh_component_descriptor descriptor_ = {
    sizeof(mh_component_descriptor),
    "point-load",
    "Constant point load",
    "example.org",
    "1.0.0",
    "A constant world-frame force at one body point. Options: force [N]; point: at."};

static uint32_t count(const mh_subsystem_factory* f) {
  (void)f;
  return 1;
}

static const mh_component_descriptor* describe(const mh_subsystem_factory* f, uint32_t i) {
  (void)f;
  return i == 0 ? &descriptor_ : NULL;
}

static const mh_subsystem* create(const mh_subsystem_factory* f, const mh_host* host,
                                  const char* id) {
  (void)f;
  if (host == NULL || id == NULL || strcmp(id, descriptor_.id) != 0) return NULL;
  point_load* d = calloc(1, sizeof *d);
  mh_subsystem* s = calloc(1, sizeof *s);
  if (d == NULL || s == NULL) {
    free(d);
    free(s);
    host->log(host, MH_LOG_ERROR, "point-load: out of memory");
    return NULL;
  }
  d->host = host;
  d->point = -1;
  s->struct_size = sizeof *s;
  s->descriptor = &descriptor_;
  s->plugin_data = d;
  s->setup = setup;
  s->evaluate = evaluate;
  s->jacobian = NULL; /* no states */
  s->energy = NULL;
  s->accept = NULL;
  s->destroy = destroy;
  s->get_extension = get_extension;
  return s;
}

/* A small model that uses the component, on which `monohydra check
 * point-load.so` checks it without a model of the user's: a double pendulum
 * pulled sideways at its tip. */
static const char* example_model(const mh_subsystem_factory* f, uint32_t i) {
  (void)f;
  return i != 0 ? NULL
                : "units: {length: m, mass: kg, time: s, angle: rad}\n"
                  "gravity: [0, -9.81, 0]\n"
                  "bodies:\n"
                  "  - {name: upper, parent: ground, joint: {type: revolute, at: [0, 0, 0], "
                  "axis: [0, 0, 1]}, mass: 1.0, shape: {type: beam, length: 1.0}}\n"
                  "  - {name: lower, parent: upper, joint: {type: revolute, at: [1, 0, 0], "
                  "axis: [0, 0, 1]}, mass: 1.0, shape: {type: beam, length: 1.0}}\n"
                  "subsystems:\n"
                  "  - {name: pull, type: point-load, force: [5, 0, 0], "
                  "points: {at: {body: lower, at: [1, 0, 0]}}}\n"
                  "formulation: open-loop\n"
                  "solver: {dt: 0.001, t_end: 1}\n";
}

static const mh_subsystem_factory factory_ = {sizeof(mh_subsystem_factory), count, describe, create,
                                              example_model};

static int init(const char* path) {
  (void)path;
  return 1;
}
static void deinit(void) {}
static const void* get_factory(const char* id) {
  return id != NULL && strcmp(id, MH_SUBSYSTEM_FACTORY_ID) == 0 ? &factory_ : NULL;
}

MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry = {MH_ABI_VERSION_INIT, init, deinit, get_factory};
