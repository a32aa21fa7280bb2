// monohydra SDK, optional C++17 helper: the part of an integrator plugin that
// is the same in every one, for a library that ships several integrators. An
// integrator writes its operations as free functions over its own state type
// T (which has a `const mh_host* host` member), wraps each body in
// monohydra::guarded_integrator_op (so that no exception crosses the C
// boundary), lists them in an mh_integrator "ops" table, and writes
//
//   const mh_integrator* create(const mh_host* host) {
//     return monohydra::create_integrator<MyState>(host, kOps);
//   }
//   const monohydra::IntegratorComponent kMine{&kDescriptor, create};
//
// The ops table's destroy can be monohydra::destroy_integrator<MyState>. One
// source file of the library then lists the integrators at global scope:
//
//   MONOHYDRA_INTEGRATOR_PLUGIN(my_ns::kMine, my_ns::kOther);
//
// which defines the factory (the integrators in that order; hosts take the
// first as the library's default) and the entry symbol `mh_entry`.
#ifndef MONOHYDRA_CPP_INTEGRATOR_PLUGIN_HPP
#define MONOHYDRA_CPP_INTEGRATOR_PLUGIN_HPP

#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <type_traits>
#include <utility>

#include "monohydra/entry.h"
#include "monohydra/integrator.h"

namespace monohydra {

namespace integrator_detail {

// Logs "<op>: <reason>" at error level without throwing (a failed allocation
// logs `op` alone).
inline void log_failure(const mh_host* host, const char* op, const char* reason) noexcept {
  if (host == nullptr || host->log == nullptr) return;
  try {
    host->log(host, MH_LOG_ERROR, (std::string(op) + ": " + reason).c_str());
  } catch (...) {
    host->log(host, MH_LOG_ERROR, op);
  }
}

}  // namespace integrator_detail

// Runs `op` (returning mh_status); an exception escaping it is logged through
// `host` as "<op_name>: <exception text>" and turns into MH_ERROR.
template <class Op>
mh_status guarded_integrator_op(const mh_host* host, const char* op_name, Op&& op) noexcept {
  try {
    return std::forward<Op>(op)();
  } catch (const std::exception& e) {
    integrator_detail::log_failure(host, op_name, e.what());
  } catch (...) {
    integrator_detail::log_failure(host, op_name, "unknown C++ exception");
  }
  return MH_ERROR;
}

// A new instance: a copy of `ops` with a fresh T as its plugin_data. NULL
// (after logging) when memory runs out or T's constructor throws.
template <class T>
const mh_integrator* create_integrator(const mh_host* host, const mh_integrator& ops) noexcept {
  if (host == nullptr) return nullptr;
  T* data = nullptr;
  try {
    data = new T;
  } catch (const std::exception& e) {
    integrator_detail::log_failure(host, "creating the integrator", e.what());
    return nullptr;
  } catch (...) {
    integrator_detail::log_failure(host, "creating the integrator", "unknown C++ exception");
    return nullptr;
  }
  auto* integrator = new (std::nothrow) mh_integrator(ops);
  if (integrator == nullptr) {
    delete data;
    integrator_detail::log_failure(host, "creating the integrator", "out of memory");
    return nullptr;
  }
  data->host = host;
  integrator->plugin_data = data;
  return integrator;
}

// The destroy operation of an instance made by create_integrator<T>.
template <class T>
void destroy_integrator(const mh_integrator* integrator) noexcept {
  if (integrator == nullptr) return;
  delete static_cast<T*>(integrator->plugin_data);
  delete integrator;
}

// One integrator of a library: its descriptor, how to create an instance and
// its example model (NULL: none).
struct IntegratorComponent {
  const mh_component_descriptor* descriptor;
  const mh_integrator* (*create)(const mh_host* host);
  const char* example_model = nullptr;
};

// The mh_integrator_factory over a fixed list of integrators (a static array
// that outlives the factory, e.g. one at namespace scope).
class IntegratorFactory {
 public:
  template <std::size_t N>
  constexpr explicit IntegratorFactory(const IntegratorComponent (&components)[N]) noexcept
      : api_{sizeof(mh_integrator_factory), count, descriptor, create, example_model},
        components_(components),
        size_(static_cast<uint32_t>(N)) {}

  const mh_integrator_factory* api() const noexcept { return &api_; }
  // For mh_plugin_entry.get_factory: this factory for MH_INTEGRATOR_FACTORY_ID, else NULL.
  const void* get_factory(const char* factory_id) const noexcept {
    return factory_id != nullptr && std::strcmp(factory_id, MH_INTEGRATOR_FACTORY_ID) == 0
               ? &api_
               : nullptr;
  }

 private:
  // The host holds &api_, which is this object's address (first member of a
  // standard-layout class): the operations below recover the object from it.
  mh_integrator_factory api_;
  const IntegratorComponent* components_;
  uint32_t size_;

  static const IntegratorFactory& self(const mh_integrator_factory* f) noexcept {
    return *reinterpret_cast<const IntegratorFactory*>(f);
  }
  static uint32_t count(const mh_integrator_factory* f) noexcept { return self(f).size_; }
  static const mh_component_descriptor* descriptor(const mh_integrator_factory* f,
                                                   uint32_t index) noexcept {
    const IntegratorFactory& factory = self(f);
    return index < factory.size_ ? factory.components_[index].descriptor : nullptr;
  }
  static const char* example_model(const mh_integrator_factory* f, uint32_t index) noexcept {
    const IntegratorFactory& factory = self(f);
    return index < factory.size_ ? factory.components_[index].example_model : nullptr;
  }
  static const mh_integrator* create(const mh_integrator_factory* f, const mh_host* host,
                                     const char* id) noexcept {
    if (host == nullptr) return nullptr;
    if (id == nullptr) {
      integrator_detail::log_failure(host, "creating an integrator", "no id given");
      return nullptr;
    }
    const IntegratorFactory& factory = self(f);
    for (uint32_t i = 0; i < factory.size_; ++i)
      if (std::strcmp(factory.components_[i].descriptor->id, id) == 0)
        return factory.components_[i].create(host);
    integrator_detail::log_failure(host, id, "no such integrator in this library");
    return nullptr;
  }
};
static_assert(std::is_standard_layout_v<IntegratorFactory>,
              "IntegratorFactory must be standard-layout: the host holds its first member");

}  // namespace monohydra

// Defines the library's entry symbol `mh_entry` (its only export) with one
// integrator factory listing the given monohydra::IntegratorComponent values
// (the first is the library's default). Use once per library, at global scope
// of one source file.
#define MONOHYDRA_INTEGRATOR_PLUGIN(...)                                                    \
  namespace {                                                                               \
  const ::monohydra::IntegratorComponent monohydra_integrator_components[] = {__VA_ARGS__}; \
  const ::monohydra::IntegratorFactory monohydra_integrator_factory(                        \
      monohydra_integrator_components);                                                     \
  int monohydra_integrator_init(const char*) {                                              \
    return 1;                                                                               \
  }                                                                                         \
  void monohydra_integrator_deinit() {}                                                     \
  const void* monohydra_integrator_get_factory(const char* id) {                            \
    return monohydra_integrator_factory.get_factory(id);                                    \
  }                                                                                         \
  }                                                                                         \
  extern "C" MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry {                              \
    MH_ABI_VERSION_INIT, monohydra_integrator_init, monohydra_integrator_deinit,            \
        monohydra_integrator_get_factory                                                    \
  }

#endif  // MONOHYDRA_CPP_INTEGRATOR_PLUGIN_HPP
