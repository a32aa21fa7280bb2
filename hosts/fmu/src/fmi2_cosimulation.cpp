// The FMI 2.0 Co-Simulation entry points of an exported FMU (FMI 2.0, 2.1
// and 4.2) over the same CoSimulation as FMI 3.0's: `monohydra fmu
// --fmi-version 2` writes a 2.0 modelDescription.xml for the same binary.
#include <cstdint>
#include <exception>
#include <new>
#include <string>

#include "cosimulation.hpp"
#include "fmu_export.hpp"
#include "monohydra/fmi/fmi2.h"
#include "resource_path.hpp"

using mh::fmu::CoSimulation;
using mh::fmu::Status;

namespace {

constexpr std::uint64_t kTag = 0x6d6f6e6f66326373ULL;  // "monof2cs"

struct Component {
  std::uint64_t tag = kTag;
  std::string name;
  fmi2CallbackLogger logger = nullptr;
  fmi2ComponentEnvironment environment = nullptr;
  double start_time = 0.0;
  bool tolerance_defined = false;
  double tolerance = 0.0;
  double last_successful_time = 0.0;
  CoSimulation* sim = nullptr;
};

Component* live(fmi2Component c) {
  auto* in = static_cast<Component*>(c);
  return in != nullptr && in->tag == kTag ? in : nullptr;
}

fmi2Status status(Status s) {
  return static_cast<fmi2Status>(static_cast<int>(s));
}

// The 2.0 logger takes a printf format: the message goes in as "%s"'s argument.
void log_through(fmi2CallbackLogger logger, fmi2ComponentEnvironment env, const std::string& name,
                 fmi2Status s, const char* category, const std::string& message) {
  if (logger != nullptr) logger(env, name.c_str(), s, category, "%s", message.c_str());
}

template <class Body>
fmi2Status call(fmi2Component c, const char* function, Body body) {
  Component* in = live(c);
  if (in == nullptr) return fmi2Error;
  try {
    return status(body(*in));
  } catch (const std::bad_alloc&) {
    return status(in->sim->refuse(function, "out of memory"));
  } catch (const std::exception& e) {
    return status(in->sim->refuse(function, e.what()));
  }
}

fmi2Status unsupported(fmi2Component c, const char* function, const char* why) {
  return call(c, function, [&](Component& in) { return in.sim->refuse(function, why); });
}

constexpr const char* kOnlyReal = "the FMU's variables are all Real (fmi2GetReal / fmi2SetReal)";

}  // namespace

extern "C" {

MH_FMU_EXPORT const char* fmi2GetTypesPlatform(void) {
  return MH_FMI2_TYPES_PLATFORM;
}
MH_FMU_EXPORT const char* fmi2GetVersion(void) {
  return MH_FMI2_VERSION;
}

MH_FMU_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn,
                                             size_t nCategories, const fmi2String categories[]) {
  (void)nCategories;
  (void)categories;
  return call(c, "fmi2SetDebugLogging", [&](Component& in) {
    in.sim->set_logging(loggingOn != fmi2False);
    return Status::ok;
  });
}

MH_FMU_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType,
                                            fmi2String fmuGUID, fmi2String fmuResourceLocation,
                                            const fmi2CallbackFunctions* functions,
                                            fmi2Boolean visible, fmi2Boolean loggingOn) {
  (void)visible;
  const std::string name = instanceName != nullptr ? instanceName : "";
  fmi2CallbackLogger logger = functions != nullptr ? functions->logger : nullptr;
  fmi2ComponentEnvironment env = functions != nullptr ? functions->componentEnvironment : nullptr;
  auto say = [&](const std::string& why) {
    log_through(logger, env, name, fmi2Error, "logStatusError", "fmi2Instantiate: " + why);
  };
  if (fmuType != fmi2CoSimulation) {
    say("this FMU is Co-Simulation only (fmuType must be fmi2CoSimulation)");
    return nullptr;
  }
  if (fmuGUID == nullptr || fmuResourceLocation == nullptr) {
    say("fmuGUID and fmuResourceLocation must not be NULL");
    return nullptr;
  }
  Component* in = nullptr;
  try {
    in = new Component();
    in->name = name;
    in->logger = logger;
    in->environment = env;
    auto log = [in](Status s, const char* category, const std::string& message) {
      log_through(in->logger, in->environment, in->name, status(s), category, message);
    };
    in->sim = new CoSimulation(mh::fmu::directory_of_resources(fmuResourceLocation), fmuGUID, log,
                               loggingOn != fmi2False);
    return in;
  } catch (const std::exception& e) {
    say(e.what());
  }
  delete in;
  return nullptr;
}

MH_FMU_EXPORT void fmi2FreeInstance(fmi2Component c) {
  Component* in = live(c);
  if (in == nullptr) return;
  in->tag = 0;
  delete in->sim;
  delete in;
}

MH_FMU_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                                             fmi2Real tolerance, fmi2Real startTime,
                                             fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  (void)stopTimeDefined;
  (void)stopTime;
  return call(c, "fmi2SetupExperiment", [&](Component& in) {
    if (in.sim->mode() != mh::fmu::Mode::instantiated)
      return in.sim->refuse("fmi2SetupExperiment", "called after initialisation began");
    in.tolerance_defined = toleranceDefined != fmi2False;
    in.tolerance = tolerance;
    in.start_time = startTime;
    return Status::ok;
  });
}

MH_FMU_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return call(c, "fmi2EnterInitializationMode", [&](Component& in) {
    return in.sim->enter_initialization(in.tolerance_defined, in.tolerance, in.start_time);
  });
}

MH_FMU_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return call(c, "fmi2ExitInitializationMode",
              [&](Component& in) { return in.sim->exit_initialization(); });
}

MH_FMU_EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
  return call(c, "fmi2Terminate", [&](Component& in) { return in.sim->terminate(); });
}

MH_FMU_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  return call(c, "fmi2Reset", [&](Component& in) {
    in.start_time = 0.0;
    in.tolerance_defined = false;
    return in.sim->reset();
  });
}

MH_FMU_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2Real value[]) {
  static_assert(sizeof(fmi2ValueReference) == sizeof(std::uint32_t));
  return call(c, "fmi2GetReal", [&](Component& in) { return in.sim->get(vr, nvr, value); });
}

MH_FMU_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2Real value[]) {
  return call(c, "fmi2SetReal", [&](Component& in) { return in.sim->set(vr, nvr, value); });
}

#define MH_FMI2_NO_VARIABLES_OF(Name, Type)                                              \
  MH_FMU_EXPORT fmi2Status fmi2Get##Name(fmi2Component c, const fmi2ValueReference vr[], \
                                         size_t nvr, Type value[]) {                     \
    (void)vr;                                                                            \
    (void)value;                                                                         \
    if (nvr == 0) return live(c) != nullptr ? fmi2OK : fmi2Error;                        \
    return unsupported(c, "fmi2Get" #Name, kOnlyReal);                                   \
  }                                                                                      \
  MH_FMU_EXPORT fmi2Status fmi2Set##Name(fmi2Component c, const fmi2ValueReference vr[], \
                                         size_t nvr, const Type value[]) {               \
    (void)vr;                                                                            \
    (void)value;                                                                         \
    if (nvr == 0) return live(c) != nullptr ? fmi2OK : fmi2Error;                        \
    return unsupported(c, "fmi2Set" #Name, kOnlyReal);                                   \
  }
MH_FMI2_NO_VARIABLES_OF(Integer, fmi2Integer)
MH_FMI2_NO_VARIABLES_OF(Boolean, fmi2Boolean)
MH_FMI2_NO_VARIABLES_OF(String, fmi2String)
#undef MH_FMI2_NO_VARIABLES_OF

MH_FMU_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* FMUstate) {
  return call(c, "fmi2GetFMUstate", [&](Component& in) { return in.sim->get_state(FMUstate); });
}

MH_FMU_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
  return call(c, "fmi2SetFMUstate", [&](Component& in) { return in.sim->set_state(FMUstate); });
}

MH_FMU_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* FMUstate) {
  return call(c, "fmi2FreeFMUstate", [&](Component& in) { return in.sim->free_state(FMUstate); });
}

MH_FMU_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate,
                                                    size_t* size) {
  return call(c, "fmi2SerializedFMUstateSize",
              [&](Component& in) { return in.sim->serialized_size(FMUstate, size); });
}

MH_FMU_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate,
                                               fmi2Byte serializedState[], size_t size) {
  return call(c, "fmi2SerializeFMUstate", [&](Component& in) {
    return in.sim->serialize(FMUstate, reinterpret_cast<std::uint8_t*>(serializedState), size);
  });
}

MH_FMU_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[],
                                                 size_t size, fmi2FMUstate* FMUstate) {
  return call(c, "fmi2DeSerializeFMUstate", [&](Component& in) {
    return in.sim->deserialize(reinterpret_cast<const std::uint8_t*>(serializedState), size,
                               FMUstate);
  });
}

MH_FMU_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c,
                                                      const fmi2ValueReference vUnknown_ref[],
                                                      size_t nUnknown,
                                                      const fmi2ValueReference vKnown_ref[],
                                                      size_t nKnown, const fmi2Real dvKnown[],
                                                      fmi2Real dvUnknown[]) {
  (void)vUnknown_ref, (void)nUnknown, (void)vKnown_ref, (void)nKnown, (void)dvKnown,
      (void)dvUnknown;
  return unsupported(c, "fmi2GetDirectionalDerivative",
                     "the FMU provides no directional derivatives");
}

MH_FMU_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                     size_t nvr, const fmi2Integer order[],
                                                     const fmi2Real value[]) {
  (void)vr, (void)nvr, (void)order, (void)value;
  return unsupported(c, "fmi2SetRealInputDerivatives",
                     "the FMU does not interpolate inputs (canInterpolateInputs=\"false\")");
}

MH_FMU_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c,
                                                      const fmi2ValueReference vr[], size_t nvr,
                                                      const fmi2Integer order[], fmi2Real value[]) {
  (void)vr, (void)nvr, (void)order, (void)value;
  return unsupported(c, "fmi2GetRealOutputDerivatives",
                     "the FMU provides no output derivatives (maxOutputDerivativeOrder 0)");
}

MH_FMU_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                    fmi2Real communicationStepSize,
                                    fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  (void)noSetFMUStatePriorToCurrentPoint;
  return call(c, "fmi2DoStep", [&](Component& in) {
    return in.sim->do_step(currentCommunicationPoint, communicationStepSize,
                           &in.last_successful_time);
  });
}

MH_FMU_EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
  return unsupported(c, "fmi2CancelStep", "fmi2DoStep never returns fmi2Pending");
}

MH_FMU_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status* value) {
  (void)s, (void)value;
  return unsupported(c, "fmi2GetStatus", "fmi2DoStep is synchronous: there is no pending status");
}

MH_FMU_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s,
                                           fmi2Real* value) {
  return call(c, "fmi2GetRealStatus", [&](Component& in) {
    if (s != fmi2LastSuccessfulTime || value == nullptr)
      return in.sim->refuse("fmi2GetRealStatus",
                            "only fmi2LastSuccessfulTime is a Real status, into a non-NULL value");
    *value = in.last_successful_time;
    return Status::ok;
  });
}

MH_FMU_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s,
                                              fmi2Integer* value) {
  (void)s, (void)value;
  return unsupported(c, "fmi2GetIntegerStatus", "the FMU has no Integer status");
}

MH_FMU_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s,
                                              fmi2Boolean* value) {
  return call(c, "fmi2GetBooleanStatus", [&](Component& in) {
    if (s != fmi2Terminated || value == nullptr)
      return in.sim->refuse("fmi2GetBooleanStatus",
                            "only fmi2Terminated is a Boolean status, into a non-NULL value");
    *value = fmi2False;
    return Status::ok;
  });
}

MH_FMU_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s,
                                             fmi2String* value) {
  (void)s, (void)value;
  return unsupported(c, "fmi2GetStringStatus", "fmi2DoStep is synchronous: no pending status");
}

}  // extern "C"
