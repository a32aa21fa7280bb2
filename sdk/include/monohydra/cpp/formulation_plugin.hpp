// monohydra SDK, optional C++17 helper: the part of a formulation plugin that
// is the same in every one. A formulation writes its operations as free
// functions over its own state type T (which has a `const mh_host* host`
// member, and may have a `const mh_mechanism_service* mech` one), each body inside
// monohydra::guarded_op so that no exception crosses into the host,
//
//   mh_status residual(const mh_formulation* f, const mh_unknown_values* at,
//                      double* r) noexcept {
//     return monohydra::guarded_op<MyState>(f, "residual", [&](MyState& s) { ... });
//   }
//
// lists them in an mh_formulation "ops" table, and writes
//
//   const mh_formulation* create(const mh_host* host) {
//     return monohydra::create_formulation<MyState>(host, kOps);
//   }
//   MONOHYDRA_FORMULATION_PLUGIN(my_ns::kDescriptor, my_ns::create)
//
// at global scope; the ops table's destroy can be monohydra::destroy_formulation<MyState>.
// The macro defines the factory (one component) and the entry symbol. setup
// declares unknowns and outputs with the spec structs of host.h
// (monohydra/cpp/specs.hpp fills them: unknown_spec, output_spec).
#ifndef MONOHYDRA_CPP_FORMULATION_PLUGIN_HPP
#define MONOHYDRA_CPP_FORMULATION_PLUGIN_HPP

#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

#include "monohydra/cpp/guarded.hpp"
#include "monohydra/cpp/services.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/entry.h"
#include "monohydra/formulation.h"

namespace monohydra {

namespace formulation_detail {
template <class T, class = void>
struct HasMech : std::false_type {};
template <class T>
struct HasMech<T, std::void_t<decltype(std::declval<T&>().mech)>> : std::true_type {};
}  // namespace formulation_detail

// Runs `op(T&)` on the instance `f` made by create_formulation<T>; an escaping
// exception is logged through the instance's host as "<what>: <text>" and
// turns into MH_ERROR (monohydra/cpp/guarded.hpp).
template <class T, class Op>
mh_status guarded_op(const mh_formulation* f, const char* what, Op&& op) noexcept {
  T& state = *static_cast<T*>(f->plugin_data);
  return guarded(state.host, what, [&] { return op(state); });
}

// A new instance: a copy of `ops` with a fresh T as its plugin_data. NULL
// (after logging) when memory runs out or T's constructor throws.
template <class T>
const mh_formulation* create_formulation(const mh_host* host, const mh_formulation& ops) noexcept {
  T* data = nullptr;
  const mh_status made = guarded(host, "creating the formulation", [&] {
    data = new (std::nothrow) T;  // T's constructor may still throw: guarded
    return MH_OK;
  });
  if (made != MH_OK) return nullptr;
  auto* f = data != nullptr ? new (std::nothrow) mh_formulation(ops) : nullptr;
  if (f == nullptr) {
    host->log(host, MH_LOG_ERROR, "creating the formulation: out of memory");
    delete data;
    return nullptr;
  }
  data->host = host;
  // A member `const mh_mechanism_service* mech` gets the mechanism service,
  // found once here (its calls are made in the time step).
  if constexpr (formulation_detail::HasMech<T>::value) data->mech = &mechanism(host);
  f->plugin_data = data;
  return f;
}

// The destroy operation of an instance made by create_formulation<T>.
template <class T>
void destroy_formulation(const mh_formulation* f) noexcept {
  delete static_cast<T*>(f->plugin_data);
  delete f;
}

}  // namespace monohydra

// The factory of one formulation and the plugin's entry symbol. `descriptor`
// is an mh_component_descriptor; `create` a function
// const mh_formulation* (const mh_host*), called inside a guard. Use once per
// plugin, at global scope. It declares no example model: `monohydra check`
// then runs the formulation on the shipped four-bar.
#define MONOHYDRA_FORMULATION_PLUGIN(descriptor, create) \
  MONOHYDRA_FORMULATION_PLUGIN_WITH_EXAMPLE(descriptor, create, nullptr)

// The same, declaring `example_model` (a const char* to the YAML text of a
// small model file that uses the formulation, living as long as the
// library; the factory's example_model): what `monohydra check PLUGIN.so`
// and the test host's check_library run it on when no model is given.
#define MONOHYDRA_FORMULATION_PLUGIN_WITH_EXAMPLE(descriptor, create, example_model)               \
  namespace {                                                                                      \
  uint32_t monohydra_formulation_count(const mh_formulation_factory*) {                            \
    return 1;                                                                                      \
  }                                                                                                \
  const mh_component_descriptor* monohydra_formulation_descriptor(const mh_formulation_factory*,   \
                                                                  uint32_t i) {                    \
    return i == 0 ? &(descriptor) : nullptr;                                                       \
  }                                                                                                \
  const mh_formulation* monohydra_formulation_create(const mh_formulation_factory*,                \
                                                     const mh_host* host, const char* id) {        \
    if (host == nullptr || id == nullptr || std::strcmp(id, (descriptor).id) != 0) return nullptr; \
    const mh_formulation* made = nullptr;                                                          \
    ::monohydra::guarded(host, "create", [&] {                                                     \
      made = create(host);                                                                         \
      return MH_OK;                                                                                \
    });                                                                                            \
    return made;                                                                                   \
  }                                                                                                \
  const char* monohydra_formulation_example_model(const mh_formulation_factory*, uint32_t i) {     \
    return i == 0 ? (example_model) : nullptr;                                                     \
  }                                                                                                \
  const mh_formulation_factory monohydra_formulation_factory{                                      \
      sizeof(mh_formulation_factory), monohydra_formulation_count,                                 \
      monohydra_formulation_descriptor, monohydra_formulation_create,                              \
      monohydra_formulation_example_model};                                                        \
  int monohydra_formulation_init(const char*) {                                                    \
    return 1;                                                                                      \
  }                                                                                                \
  void monohydra_formulation_deinit() {}                                                           \
  const void* monohydra_formulation_get_factory(const char* id) {                                  \
    return id != nullptr && std::strcmp(id, MH_FORMULATION_FACTORY_ID) == 0                        \
               ? &monohydra_formulation_factory                                                    \
               : nullptr;                                                                          \
  }                                                                                                \
  }                                                                                                \
  extern "C" MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry {                                     \
    MH_ABI_VERSION_INIT, monohydra_formulation_init, monohydra_formulation_deinit,                 \
        monohydra_formulation_get_factory                                                          \
  }

#endif  // MONOHYDRA_CPP_FORMULATION_PLUGIN_HPP
