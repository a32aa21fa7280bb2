#include "binary.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fmu {
namespace {

// The platform's folder of the FMI 3.0 layout (2.5.1): <arch>-<os>.
constexpr const char* kPlatform = "x86_64-linux";

}  // namespace

Binary::Binary(const std::string& folder, const ModelDescription& description) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path platform = fs::path(folder) / "binaries" / kPlatform;
  if (!fs::is_directory(platform, ec))
    throw std::runtime_error(std::string("it has no binary for this platform (no binaries/") +
                             kPlatform + "/ in the archive)");
  const fs::path library = platform / (description.model_identifier + ".so");
  if (!fs::is_regular_file(library, ec))
    throw std::runtime_error("it has no binaries/" + std::string(kPlatform) + "/" +
                             description.model_identifier + ".so (its modelIdentifier's library)");
  // RTLD_LOCAL: two FMUs export the same fmi3* names; each keeps its own.
  handle_ = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle_ == nullptr) {
    const char* why = dlerror();
    throw std::runtime_error("its binary does not load: " + std::string(why != nullptr ? why : ""));
  }
  std::string missing;
  const auto resolve = [&](auto*& into, const char* name) {
    into = reinterpret_cast<std::remove_reference_t<decltype(into)>>(dlsym(handle_, name));
    if (into == nullptr) missing += (missing.empty() ? "" : ", ") + std::string(name);
  };
  resolve(fmi_.instantiate, "fmi3InstantiateModelExchange");
  resolve(fmi_.free_instance, "fmi3FreeInstance");
  resolve(fmi_.enter_initialization, "fmi3EnterInitializationMode");
  resolve(fmi_.exit_initialization, "fmi3ExitInitializationMode");
  resolve(fmi_.enter_event_mode, "fmi3EnterEventMode");
  resolve(fmi_.terminate, "fmi3Terminate");
  resolve(fmi_.get_float64, "fmi3GetFloat64");
  resolve(fmi_.set_float64, "fmi3SetFloat64");
  resolve(fmi_.update_discrete_states, "fmi3UpdateDiscreteStates");
  resolve(fmi_.enter_continuous_time_mode, "fmi3EnterContinuousTimeMode");
  resolve(fmi_.completed_integrator_step, "fmi3CompletedIntegratorStep");
  resolve(fmi_.set_time, "fmi3SetTime");
  resolve(fmi_.set_continuous_states, "fmi3SetContinuousStates");
  resolve(fmi_.get_continuous_states, "fmi3GetContinuousStates");
  resolve(fmi_.get_derivatives, "fmi3GetContinuousStateDerivatives");
  if (description.provides_directional_derivatives)
    resolve(fmi_.directional_derivative, "fmi3GetDirectionalDerivative");
  if (description.can_get_and_set_state && description.can_serialize_state) {
    resolve(fmi_.get_state, "fmi3GetFMUState");
    resolve(fmi_.set_state, "fmi3SetFMUState");
    resolve(fmi_.free_state, "fmi3FreeFMUState");
    resolve(fmi_.serialized_size, "fmi3SerializedFMUStateSize");
    resolve(fmi_.serialize, "fmi3SerializeFMUState");
    resolve(fmi_.deserialize, "fmi3DeserializeFMUState");
  }
  if (!missing.empty()) {
    dlclose(handle_);
    handle_ = nullptr;
    throw std::runtime_error("its binary lacks functions the import calls: " + missing);
  }
}

Binary::~Binary() {
  if (handle_ != nullptr) dlclose(handle_);
}

}  // namespace fmu
