// The FMI 3.0 Co-Simulation entry points of an exported FMU (FMI 3.0, 2.3
// and 4.2): each checks its instance, turns the call into CoSimulation's and
// never lets an exception out. An FMU must export every function of the
// standard; those of Model Exchange, Scheduled Execution, clocks and the
// types the model has none of return fmi3Error with a message saying so.
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "cosimulation.hpp"
#include "fmu_export.hpp"
#include "monohydra/fmi/fmi3.h"
#include "resource_path.hpp"

using mh::fmu::CoSimulation;
using mh::fmu::Status;

namespace {

// What an fmi3Instance points to; `tag` tells a live instance from NULL, a
// freed one or another library's (checked by every call).
constexpr std::uint64_t kTag = 0x6d6f6e6f66336373ULL;  // "monof3cs"

struct Instance {
  std::uint64_t tag = kTag;
  std::string name;
  fmi3InstanceEnvironment environment = nullptr;
  fmi3LogMessageCallback log = nullptr;
  CoSimulation* sim = nullptr;
};

Instance* live(fmi3Instance instance) {
  auto* in = static_cast<Instance*>(instance);
  return in != nullptr && in->tag == kTag ? in : nullptr;
}

fmi3Status status(Status s) {
  return static_cast<fmi3Status>(static_cast<int>(s));
}

// Runs `body` on a live instance; an exception becomes fmi3Error with its text.
template <class Body>
fmi3Status call(fmi3Instance instance, const char* function, Body body) {
  Instance* in = live(instance);
  if (in == nullptr) return fmi3Error;  // no instance to log through
  try {
    return status(body(*in->sim));
  } catch (const std::bad_alloc&) {
    return status(in->sim->refuse(function, "out of memory"));
  } catch (const std::exception& e) {
    return status(in->sim->refuse(function, e.what()));
  }
}

fmi3Status unsupported(fmi3Instance instance, const char* function, const char* why) {
  return call(instance, function, [&](CoSimulation& s) { return s.refuse(function, why); });
}

constexpr const char* kOnlyFloat64 =
    "the FMU's variables are all Float64 (fmi3GetFloat64 / fmi3SetFloat64)";
constexpr const char* kNoModelExchange =
    "this FMU is Co-Simulation only: the model's own implicit step is the integrator";

}  // namespace

extern "C" {

MH_FMU_EXPORT const char* fmi3GetVersion(void) {
  return MH_FMI3_VERSION;
}

MH_FMU_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn,
                                             size_t nCategories, const fmi3String categories[]) {
  (void)nCategories;
  (void)categories;  // every category follows loggingOn; errors are logged always
  return call(instance, "fmi3SetDebugLogging", [&](CoSimulation& s) {
    s.set_logging(loggingOn);
    return Status::ok;
  });
}

MH_FMU_EXPORT fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName,
                                                        fmi3String instantiationToken,
                                                        fmi3String resourcePath,
                                                        fmi3Boolean visible, fmi3Boolean loggingOn,
                                                        fmi3InstanceEnvironment instanceEnvironment,
                                                        fmi3LogMessageCallback logMessage) {
  (void)instantiationToken;
  (void)resourcePath;
  (void)visible;
  (void)loggingOn;
  if (logMessage != nullptr)
    logMessage(instanceEnvironment, fmi3Error, "logStatusError",
               (std::string("fmi3InstantiateModelExchange (") +
                (instanceName != nullptr ? instanceName : "") + "): " + kNoModelExchange)
                   .c_str());
  return nullptr;
}

MH_FMU_EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
  (void)visible;
  (void)earlyReturnAllowed;  // the FMU never returns early
  (void)requiredIntermediateVariables;
  (void)intermediateUpdate;
  auto say = [&](const std::string& why) {
    if (logMessage != nullptr)
      logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                 ("fmi3InstantiateCoSimulation: " + why).c_str());
  };
  if (eventModeUsed) {
    say("the FMU has no Event Mode (hasEventMode=\"false\"): eventModeUsed must be false");
    return nullptr;
  }
  if (nRequiredIntermediateVariables > 0) {
    say("the FMU provides no intermediate update (providesIntermediateUpdate=\"false\")");
    return nullptr;
  }
  if (instantiationToken == nullptr || resourcePath == nullptr) {
    say("instantiationToken and resourcePath must not be NULL");
    return nullptr;
  }
  Instance* in = nullptr;
  try {
    in = new Instance();
    in->name = instanceName != nullptr ? instanceName : "";
    in->environment = instanceEnvironment;
    in->log = logMessage;
    auto logger = [in](Status s, const char* category, const std::string& message) {
      if (in->log != nullptr)
        in->log(in->environment, status(s), category, (in->name + ": " + message).c_str());
    };
    in->sim = new CoSimulation(mh::fmu::directory_of_resources(resourcePath), instantiationToken,
                               logger, loggingOn);
    return in;
  } catch (const std::exception& e) {
    say(e.what());
  }
  delete in;
  return nullptr;
}

MH_FMU_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
  (void)instanceName;
  (void)instantiationToken;
  (void)resourcePath;
  (void)visible;
  (void)loggingOn;
  (void)clockUpdate;
  (void)lockPreemption;
  (void)unlockPreemption;
  if (logMessage != nullptr)
    logMessage(instanceEnvironment, fmi3Error, "logStatusError",
               "fmi3InstantiateScheduledExecution: this FMU is Co-Simulation only");
  return nullptr;
}

MH_FMU_EXPORT void fmi3FreeInstance(fmi3Instance instance) {
  Instance* in = live(instance);
  if (in == nullptr) return;
  in->tag = 0;
  delete in->sim;
  delete in;
}

MH_FMU_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance instance,
                                                     fmi3Boolean toleranceDefined,
                                                     fmi3Float64 tolerance, fmi3Float64 startTime,
                                                     fmi3Boolean stopTimeDefined,
                                                     fmi3Float64 stopTime) {
  (void)stopTimeDefined;
  (void)stopTime;  // the model's t_end is no limit
  return call(instance, "fmi3EnterInitializationMode", [&](CoSimulation& s) {
    return s.enter_initialization(toleranceDefined, tolerance, startTime);
  });
}

MH_FMU_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
  return call(instance, "fmi3ExitInitializationMode",
              [&](CoSimulation& s) { return s.exit_initialization(); });
}

MH_FMU_EXPORT fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
  return unsupported(instance, "fmi3EnterEventMode", "the FMU has no Event Mode");
}

MH_FMU_EXPORT fmi3Status fmi3Terminate(fmi3Instance instance) {
  return call(instance, "fmi3Terminate", [&](CoSimulation& s) { return s.terminate(); });
}

MH_FMU_EXPORT fmi3Status fmi3Reset(fmi3Instance instance) {
  return call(instance, "fmi3Reset", [&](CoSimulation& s) { return s.reset(); });
}

MH_FMU_EXPORT fmi3Status fmi3GetFloat64(fmi3Instance instance,
                                        const fmi3ValueReference valueReferences[],
                                        size_t nValueReferences, fmi3Float64 values[],
                                        size_t nValues) {
  return call(instance, "fmi3GetFloat64", [&](CoSimulation& s) {
    if (nValues != nValueReferences)
      return s.refuse("fmi3GetFloat64",
                      "nValues (" + std::to_string(nValues) + ") differs from nValueReferences (" +
                          std::to_string(nValueReferences) + "): the FMU's variables are scalars");
    return s.get(valueReferences, nValueReferences, values);
  });
}

MH_FMU_EXPORT fmi3Status fmi3SetFloat64(fmi3Instance instance,
                                        const fmi3ValueReference valueReferences[],
                                        size_t nValueReferences, const fmi3Float64 values[],
                                        size_t nValues) {
  return call(instance, "fmi3SetFloat64", [&](CoSimulation& s) {
    if (nValues != nValueReferences)
      return s.refuse("fmi3SetFloat64",
                      "nValues (" + std::to_string(nValues) + ") differs from nValueReferences (" +
                          std::to_string(nValueReferences) + "): the FMU's variables are scalars");
    return s.set(valueReferences, nValueReferences, values);
  });
}

// The types the FMU has no variables of: a value reference given to them is unknown.
#define MH_FMI3_NO_VARIABLES_OF(Name, Type)                                                    \
  MH_FMU_EXPORT fmi3Status fmi3Get##Name(fmi3Instance instance, const fmi3ValueReference vr[], \
                                         size_t nvr, Type values[], size_t nValues) {          \
    (void)vr;                                                                                  \
    (void)values;                                                                              \
    (void)nValues;                                                                             \
    if (nvr == 0) return live(instance) != nullptr ? fmi3OK : fmi3Error;                       \
    return unsupported(instance, "fmi3Get" #Name, kOnlyFloat64);                               \
  }                                                                                            \
  MH_FMU_EXPORT fmi3Status fmi3Set##Name(fmi3Instance instance, const fmi3ValueReference vr[], \
                                         size_t nvr, const Type values[], size_t nValues) {    \
    (void)vr;                                                                                  \
    (void)values;                                                                              \
    (void)nValues;                                                                             \
    if (nvr == 0) return live(instance) != nullptr ? fmi3OK : fmi3Error;                       \
    return unsupported(instance, "fmi3Set" #Name, kOnlyFloat64);                               \
  }
MH_FMI3_NO_VARIABLES_OF(Float32, fmi3Float32)
MH_FMI3_NO_VARIABLES_OF(Int8, fmi3Int8)
MH_FMI3_NO_VARIABLES_OF(UInt8, fmi3UInt8)
MH_FMI3_NO_VARIABLES_OF(Int16, fmi3Int16)
MH_FMI3_NO_VARIABLES_OF(UInt16, fmi3UInt16)
MH_FMI3_NO_VARIABLES_OF(Int32, fmi3Int32)
MH_FMI3_NO_VARIABLES_OF(UInt32, fmi3UInt32)
MH_FMI3_NO_VARIABLES_OF(Int64, fmi3Int64)
MH_FMI3_NO_VARIABLES_OF(UInt64, fmi3UInt64)
MH_FMI3_NO_VARIABLES_OF(Boolean, fmi3Boolean)
MH_FMI3_NO_VARIABLES_OF(String, fmi3String)
#undef MH_FMI3_NO_VARIABLES_OF

MH_FMU_EXPORT fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[],
                                       size_t nvr, size_t valueSizes[], fmi3Binary values[],
                                       size_t nValues) {
  (void)vr;
  (void)valueSizes;
  (void)values;
  (void)nValues;
  if (nvr == 0) return live(instance) != nullptr ? fmi3OK : fmi3Error;
  return unsupported(instance, "fmi3GetBinary", kOnlyFloat64);
}

MH_FMU_EXPORT fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[],
                                       size_t nvr, const size_t valueSizes[],
                                       const fmi3Binary values[], size_t nValues) {
  (void)vr;
  (void)valueSizes;
  (void)values;
  (void)nValues;
  if (nvr == 0) return live(instance) != nullptr ? fmi3OK : fmi3Error;
  return unsupported(instance, "fmi3SetBinary", kOnlyFloat64);
}

MH_FMU_EXPORT fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[],
                                      size_t nvr, fmi3Clock values[]) {
  (void)vr;
  (void)nvr;
  (void)values;
  return unsupported(instance, "fmi3GetClock", "the FMU has no clocks");
}

MH_FMU_EXPORT fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[],
                                      size_t nvr, const fmi3Clock values[]) {
  (void)vr;
  (void)nvr;
  (void)values;
  return unsupported(instance, "fmi3SetClock", "the FMU has no clocks");
}

// Dependencies are not declared in the modelDescription (every output may
// depend on every input): zero listed means "not known" is not allowed, so
// the call says so.
MH_FMU_EXPORT fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                                             fmi3ValueReference valueReference,
                                                             size_t* nDependencies) {
  (void)valueReference;
  (void)nDependencies;
  return unsupported(instance, "fmi3GetNumberOfVariableDependencies",
                     "the FMU declares no dependencies (every output may depend on every input)");
}

MH_FMU_EXPORT fmi3Status fmi3GetVariableDependencies(
    fmi3Instance instance, fmi3ValueReference dependent, size_t elementIndicesOfDependent[],
    fmi3ValueReference independents[], size_t elementIndicesOfIndependents[],
    fmi3DependencyKind dependencyKinds[], size_t nDependencies) {
  (void)dependent;
  (void)elementIndicesOfDependent;
  (void)independents;
  (void)elementIndicesOfIndependents;
  (void)dependencyKinds;
  (void)nDependencies;
  return unsupported(instance, "fmi3GetVariableDependencies",
                     "the FMU declares no dependencies (every output may depend on every input)");
}

MH_FMU_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  return call(instance, "fmi3GetFMUState", [&](CoSimulation& s) { return s.get_state(FMUState); });
}

MH_FMU_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
  return call(instance, "fmi3SetFMUState", [&](CoSimulation& s) { return s.set_state(FMUState); });
}

MH_FMU_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState* FMUState) {
  return call(instance, "fmi3FreeFMUState",
              [&](CoSimulation& s) { return s.free_state(FMUState); });
}

MH_FMU_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState,
                                                    size_t* size) {
  return call(instance, "fmi3SerializedFMUStateSize",
              [&](CoSimulation& s) { return s.serialized_size(FMUState, size); });
}

MH_FMU_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                               fmi3Byte serializedState[], size_t size) {
  return call(instance, "fmi3SerializeFMUState",
              [&](CoSimulation& s) { return s.serialize(FMUState, serializedState, size); });
}

MH_FMU_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance instance,
                                                 const fmi3Byte serializedState[], size_t size,
                                                 fmi3FMUState* FMUState) {
  return call(instance, "fmi3DeserializeFMUState",
              [&](CoSimulation& s) { return s.deserialize(serializedState, size, FMUState); });
}

MH_FMU_EXPORT fmi3Status fmi3GetDirectionalDerivative(
    fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
    fmi3Float64 sensitivity[], size_t nSensitivity) {
  (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed;
  (void)sensitivity, (void)nSensitivity;
  return unsupported(instance, "fmi3GetDirectionalDerivative",
                     "the FMU provides no directional derivatives "
                     "(providesDirectionalDerivatives=\"false\")");
}

MH_FMU_EXPORT fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance,
                                                  const fmi3ValueReference unknowns[],
                                                  size_t nUnknowns,
                                                  const fmi3ValueReference knowns[], size_t nKnowns,
                                                  const fmi3Float64 seed[], size_t nSeed,
                                                  fmi3Float64 sensitivity[], size_t nSensitivity) {
  (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed;
  (void)sensitivity, (void)nSensitivity;
  return unsupported(instance, "fmi3GetAdjointDerivative",
                     "the FMU provides no adjoint derivatives");
}

MH_FMU_EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
  return unsupported(instance, "fmi3EnterConfigurationMode",
                     "the FMU has no structural parameters");
}

MH_FMU_EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
  return unsupported(instance, "fmi3ExitConfigurationMode", "the FMU has no structural parameters");
}

#define MH_FMI3_NO_CLOCKS(function, ...)                                  \
  MH_FMU_EXPORT fmi3Status function(fmi3Instance instance, __VA_ARGS__) { \
    return unsupported(instance, #function, "the FMU has no clocks");     \
  }
MH_FMI3_NO_CLOCKS(fmi3GetIntervalDecimal, const fmi3ValueReference[], size_t, fmi3Float64[],
                  fmi3IntervalQualifier[])
MH_FMI3_NO_CLOCKS(fmi3GetIntervalFraction, const fmi3ValueReference[], size_t, fmi3UInt64[],
                  fmi3UInt64[], fmi3IntervalQualifier[])
MH_FMI3_NO_CLOCKS(fmi3GetShiftDecimal, const fmi3ValueReference[], size_t, fmi3Float64[])
MH_FMI3_NO_CLOCKS(fmi3GetShiftFraction, const fmi3ValueReference[], size_t, fmi3UInt64[],
                  fmi3UInt64[])
MH_FMI3_NO_CLOCKS(fmi3SetIntervalDecimal, const fmi3ValueReference[], size_t, const fmi3Float64[])
MH_FMI3_NO_CLOCKS(fmi3SetIntervalFraction, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                  const fmi3UInt64[])
MH_FMI3_NO_CLOCKS(fmi3SetShiftDecimal, const fmi3ValueReference[], size_t, const fmi3Float64[])
MH_FMI3_NO_CLOCKS(fmi3SetShiftFraction, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                  const fmi3UInt64[])
MH_FMI3_NO_CLOCKS(fmi3ActivateModelPartition, fmi3ValueReference, fmi3Float64)
#undef MH_FMI3_NO_CLOCKS

MH_FMU_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
  return unsupported(instance, "fmi3EvaluateDiscreteStates", "the FMU has no Event Mode");
}

MH_FMU_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* a,
                                                  fmi3Boolean* b, fmi3Boolean* c, fmi3Boolean* d,
                                                  fmi3Boolean* e, fmi3Float64* f) {
  (void)a, (void)b, (void)c, (void)d, (void)e, (void)f;
  return unsupported(instance, "fmi3UpdateDiscreteStates", "the FMU has no Event Mode");
}

#define MH_FMI3_NO_ME(function, ...)                                      \
  MH_FMU_EXPORT fmi3Status function(fmi3Instance instance, __VA_ARGS__) { \
    return unsupported(instance, #function, kNoModelExchange);            \
  }
MH_FMU_EXPORT fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
  return unsupported(instance, "fmi3EnterContinuousTimeMode", kNoModelExchange);
}
MH_FMI3_NO_ME(fmi3CompletedIntegratorStep, fmi3Boolean, fmi3Boolean*, fmi3Boolean*)
MH_FMI3_NO_ME(fmi3SetTime, fmi3Float64)
MH_FMI3_NO_ME(fmi3SetContinuousStates, const fmi3Float64[], size_t)
MH_FMI3_NO_ME(fmi3GetContinuousStateDerivatives, fmi3Float64[], size_t)
MH_FMI3_NO_ME(fmi3GetEventIndicators, fmi3Float64[], size_t)
MH_FMI3_NO_ME(fmi3GetContinuousStates, fmi3Float64[], size_t)
MH_FMI3_NO_ME(fmi3GetNominalsOfContinuousStates, fmi3Float64[], size_t)
MH_FMI3_NO_ME(fmi3GetNumberOfEventIndicators, size_t*)
MH_FMI3_NO_ME(fmi3GetNumberOfContinuousStates, size_t*)
#undef MH_FMI3_NO_ME

MH_FMU_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
  return unsupported(instance, "fmi3EnterStepMode",
                     "the FMU has no Event Mode: it is in Step Mode after initialisation");
}

MH_FMU_EXPORT fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance,
                                                  const fmi3ValueReference valueReferences[],
                                                  size_t nValueReferences, const fmi3Int32 orders[],
                                                  fmi3Float64 values[], size_t nValues) {
  (void)valueReferences, (void)nValueReferences, (void)orders, (void)values, (void)nValues;
  return unsupported(instance, "fmi3GetOutputDerivatives",
                     "the FMU provides no output derivatives (maxOutputDerivativeOrder 0)");
}

MH_FMU_EXPORT fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                                    fmi3Float64 communicationStepSize,
                                    fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                    fmi3Boolean* eventHandlingNeeded,
                                    fmi3Boolean* terminateSimulation, fmi3Boolean* earlyReturn,
                                    fmi3Float64* lastSuccessfulTime) {
  (void)noSetFMUStatePriorToCurrentPoint;
  return call(instance, "fmi3DoStep", [&](CoSimulation& s) {
    if (eventHandlingNeeded != nullptr) *eventHandlingNeeded = false;
    if (terminateSimulation != nullptr) *terminateSimulation = false;
    if (earlyReturn != nullptr) *earlyReturn = false;
    return s.do_step(currentCommunicationPoint, communicationStepSize, lastSuccessfulTime);
  });
}

}  // extern "C"
