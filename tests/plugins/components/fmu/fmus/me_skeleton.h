/* The FMI 3.0 Model Exchange functions of the tests' FMUs, over one array of
 * Float64 variables indexed by valueReference (v[0] is time). A model file
 * (plant.c, pi.c) defines, before including this:
 *   NVR, NX                the variables' and the continuous states' counts
 *   STATE_VR, DER_VR       static const unsigned[NX]: states and derivatives
 *   START                  static const double[NVR]: start values
 *   model_compute(v)       the derivatives and outputs from the rest
 *   model_event(v, *next)  the discrete update; returns 1 with *next set
 *                          when a time event is due later
 *   model_partial(v, unknown, known)  when MH_WITH_DD: d unknown / d known
 * and MH_TOKEN (the instantiation token its modelDescription.xml must give).
 * MH_READ_RESOURCE reads the first state's start from resources/start.txt.
 * MH_OMIT_DERIVATIVES leaves fmi3GetContinuousStateDerivatives out (an FMU
 * that lacks a function). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "monohydra/fmi/fmi3.h"

#define MH_EXPORT __attribute__((visibility("default")))

typedef struct {
  double v[NVR];
  fmi3InstanceEnvironment env;
  fmi3LogMessageCallback log;
} Instance;

static int bad_vr(const fmi3ValueReference vr[], size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (vr[i] >= NVR) return 1;
  return 0;
}

MH_EXPORT fmi3GetVersionTYPE fmi3GetVersion;
const char* fmi3GetVersion(void) {
  return "3.0";
}

MH_EXPORT fmi3InstantiateModelExchangeTYPE fmi3InstantiateModelExchange;
fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
                                          fmi3Boolean visible, fmi3Boolean logging,
                                          fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
  (void)name;
  (void)resources;
  (void)visible;
  (void)logging;
  if (token == NULL || strcmp(token, MH_TOKEN) != 0) {
    if (log != NULL) log(env, fmi3Error, "logStatusError", "wrong instantiation token");
    return NULL;
  }
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  memcpy(in->v, START, sizeof in->v);
#ifdef MH_READ_RESOURCE
  /* The first state's start from resources/start.txt: resourcePath ends with '/'. */
  char path[4096];
  FILE* file = NULL;
  if (resources != NULL && strlen(resources) + 10 < sizeof path) {
    strcpy(path, resources);
    strcat(path, "start.txt");
    file = fopen(path, "r");
  }
  if (file == NULL || fscanf(file, "%lf", &in->v[STATE_VR[0]]) != 1) {
    if (file != NULL) fclose(file);
    if (log != NULL) log(env, fmi3Error, "logStatusError", "no resources/start.txt");
    free(in);
    return NULL;
  }
  fclose(file);
#endif
  in->env = env;
  in->log = log;
  return in;
}

MH_EXPORT fmi3FreeInstanceTYPE fmi3FreeInstance;
void fmi3FreeInstance(fmi3Instance instance) {
  free(instance);
}

MH_EXPORT fmi3SetDebugLoggingTYPE fmi3SetDebugLogging;
fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean on, size_t n,
                               const fmi3String categories[]) {
  (void)instance;
  (void)on;
  (void)n;
  (void)categories;
  return fmi3OK;
}

MH_EXPORT fmi3EnterInitializationModeTYPE fmi3EnterInitializationMode;
fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tolerance_defined,
                                       fmi3Float64 tolerance, fmi3Float64 start,
                                       fmi3Boolean stop_defined, fmi3Float64 stop) {
  (void)tolerance_defined;
  (void)tolerance;
  (void)stop_defined;
  (void)stop;
  ((Instance*)instance)->v[0] = start;
  return fmi3OK;
}

#define MH_TRIVIAL(Name)                         \
  MH_EXPORT fmi3##Name##TYPE fmi3##Name;         \
  fmi3Status fmi3##Name(fmi3Instance instance) { \
    (void)instance;                              \
    return fmi3OK;                               \
  }
MH_TRIVIAL(ExitInitializationMode)
MH_TRIVIAL(EnterEventMode)
MH_TRIVIAL(EnterContinuousTimeMode)
MH_TRIVIAL(Terminate)
MH_TRIVIAL(Reset)

MH_EXPORT fmi3GetFloat64TYPE fmi3GetFloat64;
fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                          fmi3Float64 values[], size_t nv) {
  Instance* in = (Instance*)instance;
  if (n != nv || bad_vr(vr, n)) return fmi3Error;
  model_compute(in->v);
  for (size_t i = 0; i < n; ++i) values[i] = in->v[vr[i]];
  return fmi3OK;
}

MH_EXPORT fmi3SetFloat64TYPE fmi3SetFloat64;
fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 values[], size_t nv) {
  Instance* in = (Instance*)instance;
  if (n != nv || bad_vr(vr, n)) return fmi3Error;
  for (size_t i = 0; i < n; ++i) in->v[vr[i]] = values[i];
  return fmi3OK;
}

MH_EXPORT fmi3UpdateDiscreteStatesTYPE fmi3UpdateDiscreteStates;
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* again,
                                    fmi3Boolean* terminate, fmi3Boolean* nominals,
                                    fmi3Boolean* changed, fmi3Boolean* defined, fmi3Float64* next) {
  Instance* in = (Instance*)instance;
  *again = false;
  *terminate = false;
  *nominals = false;
  *changed = false;
  *defined = model_event(in->v, next) != 0;
  return fmi3OK;
}

MH_EXPORT fmi3CompletedIntegratorStepTYPE fmi3CompletedIntegratorStep;
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean no_prior,
                                       fmi3Boolean* enter, fmi3Boolean* terminate) {
  (void)instance;
  (void)no_prior;
  *enter = false;
  *terminate = false;
  return fmi3OK;
}

MH_EXPORT fmi3SetTimeTYPE fmi3SetTime;
fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
  ((Instance*)instance)->v[0] = time;
  return fmi3OK;
}

MH_EXPORT fmi3SetContinuousStatesTYPE fmi3SetContinuousStates;
fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t n) {
  Instance* in = (Instance*)instance;
  if (n != NX) return fmi3Error;
  for (size_t i = 0; i < n; ++i) in->v[STATE_VR[i]] = x[i];
  return fmi3OK;
}

MH_EXPORT fmi3GetContinuousStatesTYPE fmi3GetContinuousStates;
fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t n) {
  Instance* in = (Instance*)instance;
  if (n != NX) return fmi3Error;
  for (size_t i = 0; i < n; ++i) x[i] = in->v[STATE_VR[i]];
  return fmi3OK;
}

#ifdef MH_OMIT_DERIVATIVES
static const unsigned* const derivatives_left_out = DER_VR; /* (read, so it is not unused) */
const unsigned* mh_derivatives_left_out(void);
MH_EXPORT const unsigned* mh_derivatives_left_out(void) {
  return derivatives_left_out;
}
#else
MH_EXPORT fmi3GetContinuousStateDerivativesTYPE fmi3GetContinuousStateDerivatives;
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 dx[], size_t n) {
  Instance* in = (Instance*)instance;
  if (n != NX) return fmi3Error;
  model_compute(in->v);
  for (size_t i = 0; i < n; ++i) dx[i] = in->v[DER_VR[i]];
  return fmi3OK;
}
#endif

#ifdef MH_WITH_DD
MH_EXPORT fmi3GetDirectionalDerivativeTYPE fmi3GetDirectionalDerivative;
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                        size_t n_unknowns, const fmi3ValueReference knowns[],
                                        size_t n_knowns, const fmi3Float64 seed[], size_t n_seed,
                                        fmi3Float64 sensitivity[], size_t n_sensitivity) {
  Instance* in = (Instance*)instance;
  if (n_seed != n_knowns || n_sensitivity != n_unknowns || bad_vr(unknowns, n_unknowns) ||
      bad_vr(knowns, n_knowns))
    return fmi3Error;
  for (size_t i = 0; i < n_unknowns; ++i) {
    sensitivity[i] = 0.0;
    for (size_t j = 0; j < n_knowns; ++j)
      sensitivity[i] += model_partial(in->v, unknowns[i], knowns[j]) * seed[j];
  }
  return fmi3OK;
}
#endif

/* The FMU state: a copy of the variables. */
MH_EXPORT fmi3GetFMUStateTYPE fmi3GetFMUState;
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* state) {
  if (*state == NULL) *state = malloc(sizeof(double) * NVR);
  if (*state == NULL) return fmi3Error;
  memcpy(*state, ((Instance*)instance)->v, sizeof(double) * NVR);
  return fmi3OK;
}

MH_EXPORT fmi3SetFMUStateTYPE fmi3SetFMUState;
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
  memcpy(((Instance*)instance)->v, state, sizeof(double) * NVR);
  return fmi3OK;
}

MH_EXPORT fmi3FreeFMUStateTYPE fmi3FreeFMUState;
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* state) {
  (void)instance;
  free(*state);
  *state = NULL;
  return fmi3OK;
}

MH_EXPORT fmi3SerializedFMUStateSizeTYPE fmi3SerializedFMUStateSize;
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t* size) {
  (void)instance;
  (void)state;
  *size = sizeof(double) * NVR;
  return fmi3OK;
}

MH_EXPORT fmi3SerializeFMUStateTYPE fmi3SerializeFMUState;
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[],
                                 size_t size) {
  (void)instance;
  if (size != sizeof(double) * NVR) return fmi3Error;
  memcpy(bytes, state, size);
  return fmi3OK;
}

MH_EXPORT fmi3DeserializeFMUStateTYPE fmi3DeserializeFMUState;
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size,
                                   fmi3FMUState* state) {
  (void)instance;
  if (size != sizeof(double) * NVR) return fmi3Error;
  if (*state == NULL) *state = malloc(size);
  if (*state == NULL) return fmi3Error;
  memcpy(*state, bytes, size);
  return fmi3OK;
}
