// An FMU's shared library (binaries/x86_64-linux/<modelIdentifier>.so),
// dlopen'ed with its own symbols kept local, and the fmi3* functions the
// import calls, resolved by name once: nothing is looked up in the time step.
#pragma once

#include <string>

#include "model_description.hpp"
#include "monohydra/fmi/fmi3.h"

namespace fmu {

struct Functions {
  fmi3InstantiateModelExchangeTYPE* instantiate = nullptr;
  fmi3FreeInstanceTYPE* free_instance = nullptr;
  fmi3EnterInitializationModeTYPE* enter_initialization = nullptr;
  fmi3ExitInitializationModeTYPE* exit_initialization = nullptr;
  fmi3EnterEventModeTYPE* enter_event_mode = nullptr;
  fmi3TerminateTYPE* terminate = nullptr;
  fmi3GetFloat64TYPE* get_float64 = nullptr;
  fmi3SetFloat64TYPE* set_float64 = nullptr;
  fmi3UpdateDiscreteStatesTYPE* update_discrete_states = nullptr;
  fmi3EnterContinuousTimeModeTYPE* enter_continuous_time_mode = nullptr;
  fmi3CompletedIntegratorStepTYPE* completed_integrator_step = nullptr;
  fmi3SetTimeTYPE* set_time = nullptr;
  fmi3SetContinuousStatesTYPE* set_continuous_states = nullptr;
  fmi3GetContinuousStatesTYPE* get_continuous_states = nullptr;
  fmi3GetContinuousStateDerivativesTYPE* get_derivatives = nullptr;
  // Only when modelDescription.xml offers them (else NULL):
  fmi3GetDirectionalDerivativeTYPE* directional_derivative = nullptr;
  fmi3GetFMUStateTYPE* get_state = nullptr;
  fmi3SetFMUStateTYPE* set_state = nullptr;
  fmi3FreeFMUStateTYPE* free_state = nullptr;
  fmi3SerializedFMUStateSizeTYPE* serialized_size = nullptr;
  fmi3SerializeFMUStateTYPE* serialize = nullptr;
  fmi3DeserializeFMUStateTYPE* deserialize = nullptr;
};

class Binary {
 public:
  Binary() = default;
  // Loads `folder`/binaries/x86_64-linux/<model_identifier>.so and resolves
  // the functions `description` needs. Throws std::runtime_error: no binary
  // for this platform, dlopen's reason, or the missing functions by name.
  Binary(const std::string& folder, const ModelDescription& description);
  ~Binary();
  Binary(const Binary&) = delete;
  Binary& operator=(const Binary&) = delete;

  const Functions& fmi() const { return fmi_; }

 private:
  void* handle_ = nullptr;
  Functions fmi_;
};

}  // namespace fmu
