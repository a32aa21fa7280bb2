// monohydra SDK, optional C++17 layer (header-only): turns a C++ class into an
// mh_subsystem, and a list of such classes into the plugin's one entry symbol,
// so a plugin writes its equations and none of the C ABI's boilerplate.
//
// Everything here is compiled into the plugin; only the plain C structs of
// monohydra/*.h cross the boundary, and no exception ever does (each operation
// catches, logs through the host and returns MH_ERROR).
//
// A component is a class T with
//
//   static const mh_component_descriptor kDescriptor;   // id, name, ...
//   explicit T(const mh_host* host);                      // may throw
//   mh_status setup();
//   mh_status evaluate(const mh_subsystem_eval& eval);    // pure
//
// and, optionally (found at compile time; absent means NULL in the table, so
// the host falls back as docs/sdk.md says):
//
//   mh_status jacobian(const mh_subsystem_eval& eval, double* d_dy, double* d_dydot);
//   mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation);
//   mh_status accept(const mh_subsystem_eval& eval);
//   const void* extension(const char* id);                // NULL if not supported
//   mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
//                                  double* dF_dv);
//   mh_status coupling_jacobian(const mh_subsystem_eval& eval, double* dR_dp, double* dR_dv,
//                               double* dF_dy, double* dF_dydot);
//   static constexpr const char* kExampleModel = R"(...)";  // a small model file (YAML)
//                               // using it, for `monohydra check PLUGIN.so`
//
// Every matrix is column-major (subsystem.h).
//
// setup declares states and outputs with the spec structs of host.h
// (mh_state_spec, mh_output_spec; monohydra/cpp/specs.hpp fills them).
//
// The library then lists its components once:
//
//   MONOHYDRA_SUBSYSTEM_PLUGIN(monohydra::subsystem_component<Spring>(),
//                              monohydra::subsystem_component<Damper>())
//
// or, with components defined in other files, `extern const
// monohydra::SubsystemComponent kSpring;` values defined there as
// `const monohydra::SubsystemComponent kSpring = monohydra::subsystem_component<Spring>();`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <utility>

#include "monohydra/cpp/guarded.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "monohydra/cpp/parameters.hpp"
#include "monohydra/cpp/specs.hpp"
#include "monohydra/entry.h"
#include "monohydra/subsystem.h"

// True when the table `table` of C type `type` (e.g. a host's mh_host) is
// large enough to hold `field`: fields a later minor ABI appended are only
// there when the other side was built against that minor version or newer.
//   if (MONOHYDRA_HAS_FIELD(mh_options_service, options, some_3_1_field)) ...
#define MONOHYDRA_HAS_FIELD(type, table, field) \
  ((table)->struct_size >= offsetof(type, field) + sizeof(type::field))

namespace monohydra {

namespace detail {

template <class T, class = void>
struct HasJacobian : std::false_type {};
template <class T>
struct HasJacobian<T, std::void_t<decltype(std::declval<T&>().jacobian(
                          std::declval<const mh_subsystem_eval&>(), std::declval<double*>(),
                          std::declval<double*>()))>> : std::true_type {};

template <class T, class = void>
struct HasPointForceJacobian : std::false_type {};
template <class T>
struct HasPointForceJacobian<T, std::void_t<decltype(std::declval<T&>().point_force_jacobian(
                                    std::declval<const mh_subsystem_eval&>(),
                                    std::declval<double*>(), std::declval<double*>()))>>
    : std::true_type {};

template <class T, class = void>
struct HasCouplingJacobian : std::false_type {};
template <class T>
struct HasCouplingJacobian<
    T, std::void_t<decltype(std::declval<T&>().coupling_jacobian(
           std::declval<const mh_subsystem_eval&>(), std::declval<double*>(),
           std::declval<double*>(), std::declval<double*>(), std::declval<double*>()))>>
    : std::true_type {};

template <class T, class = void>
struct HasEnergy : std::false_type {};
template <class T>
struct HasEnergy<T, std::void_t<decltype(std::declval<T&>().energy(
                        std::declval<const mh_subsystem_eval&>(), std::declval<double&>(),
                        std::declval<double&>()))>> : std::true_type {};

template <class T, class = void>
struct HasAccept : std::false_type {};
template <class T>
struct HasAccept<
    T, std::void_t<decltype(std::declval<T&>().accept(std::declval<const mh_subsystem_eval&>()))>>
    : std::true_type {};

template <class T, class = void>
struct HasExtension : std::false_type {};
template <class T>
struct HasExtension<
    T, std::void_t<decltype(std::declval<T&>().extension(std::declval<const char*>()))>>
    : std::true_type {};

template <class T, class = void>
struct HasParameters : std::false_type {};
template <class T>
struct HasParameters<T,
                     std::void_t<decltype(std::size(T::kParameters)),
                                 decltype(std::declval<const T&>().parameter(std::uint32_t{})),
                                 decltype(std::declval<T&>().set_parameter(std::uint32_t{}, 0.0))>>
    : std::true_type {};

// The same, with a list set up from the instance's options (a table's
// points): parameter_count() and parameter_spec(index) instead of kParameters.
template <class T, class = void>
struct HasParameterList : std::false_type {};
template <class T>
struct HasParameterList<
    T, std::void_t<decltype(static_cast<std::uint32_t>(std::declval<const T&>().parameter_count())),
                   decltype(static_cast<ParameterSpec>(
                       std::declval<const T&>().parameter_spec(std::uint32_t{}))),
                   decltype(std::declval<const T&>().parameter(std::uint32_t{})),
                   decltype(std::declval<T&>().set_parameter(std::uint32_t{}, 0.0))>>
    : std::true_type {};

template <class T, class = void>
struct HasExampleModel : std::false_type {};
template <class T>
struct HasExampleModel<T, std::void_t<decltype(static_cast<const char*>(T::kExampleModel))>>
    : std::true_type {};

}  // namespace detail

// One component of a library: its descriptor, how to create an instance and
// its example model (NULL: none).
struct SubsystemComponent {
  const mh_component_descriptor* descriptor;
  const mh_subsystem* (*create)(const mh_host* host);
  const char* example_model;
};

// The mh_subsystem of a C++ component class T (see the top of this file).
template <class T>
class SubsystemAdapter {
 public:
  // A new instance, or NULL after logging why (T's constructor threw, or no
  // memory). The host releases it through its `destroy`.
  static const mh_subsystem* create(const mh_host* host) noexcept {
    if (host == nullptr) return nullptr;
    std::unique_ptr<Instance> instance(new (std::nothrow) Instance);
    if (instance == nullptr) {
      detail::log_failure(host, T::kDescriptor.id, "out of memory");
      return nullptr;
    }
    instance->host = host;
    const mh_status made = guarded(host, "creating the instance", [&] {
      instance->object = std::make_unique<T>(host);
      return MH_OK;
    });
    if (made != MH_OK) return nullptr;
    mh_subsystem& api = instance->api;
    api.struct_size = sizeof(mh_subsystem);
    api.descriptor = &T::kDescriptor;
    api.plugin_data = instance.get();
    api.setup = setup;
    api.evaluate = evaluate;
    api.jacobian = jacobian_op();
    api.energy = energy_op();
    api.accept = accept_op();
    api.destroy = destroy;
    api.get_extension = get_extension;
    api.point_force_jacobian = point_force_jacobian_op();
    api.coupling_jacobian = coupling_jacobian_op();
    return &instance.release()->api;
  }

  // The T behind an instance table this adapter made: the `instance`
  // argument of an extension's operations (state.h) is that table.
  static T& object_of(const void* instance) noexcept {
    return *self(static_cast<const mh_subsystem*>(instance)).object;
  }

 private:
  struct Instance {
    mh_subsystem api{};
    const mh_host* host = nullptr;
    std::unique_ptr<T> object;
  };
  using JacobianOp = mh_status (*)(const mh_subsystem*, const mh_subsystem_eval*, double*, double*);
  using EnergyOp = mh_status (*)(const mh_subsystem*, const mh_subsystem_eval*, double*, double*);
  using AcceptOp = mh_status (*)(const mh_subsystem*, const mh_subsystem_eval*);
  using CouplingOp = mh_status (*)(const mh_subsystem*, const mh_subsystem_eval*, double*, double*,
                                   double*, double*);

  static Instance& self(const mh_subsystem* s) { return *static_cast<Instance*>(s->plugin_data); }

  static mh_status setup(const mh_subsystem* s) noexcept {
    Instance& i = self(s);
    return guarded(i.host, "setup", [&] { return i.object->setup(); });
  }
  static mh_status evaluate(const mh_subsystem* s, const mh_subsystem_eval* eval) noexcept {
    Instance& i = self(s);
    return guarded(i.host, "evaluate", [&] { return i.object->evaluate(*eval); });
  }
  static JacobianOp jacobian_op() {
    if constexpr (detail::HasJacobian<T>::value) {
      return [](const mh_subsystem* s, const mh_subsystem_eval* eval, double* d_dy,
                double* d_dydot) noexcept {
        Instance& i = self(s);
        return guarded(i.host, "jacobian",
                       [&] { return i.object->jacobian(*eval, d_dy, d_dydot); });
      };
    } else {
      return nullptr;
    }
  }
  static JacobianOp point_force_jacobian_op() {
    if constexpr (detail::HasPointForceJacobian<T>::value) {
      return [](const mh_subsystem* s, const mh_subsystem_eval* eval, double* dF_dp,
                double* dF_dv) noexcept {
        Instance& i = self(s);
        return guarded(i.host, "point_force_jacobian",
                       [&] { return i.object->point_force_jacobian(*eval, dF_dp, dF_dv); });
      };
    } else {
      return nullptr;
    }
  }
  static CouplingOp coupling_jacobian_op() {
    if constexpr (detail::HasCouplingJacobian<T>::value) {
      return [](const mh_subsystem* s, const mh_subsystem_eval* eval, double* dR_dp, double* dR_dv,
                double* dF_dy, double* dF_dydot) noexcept {
        Instance& i = self(s);
        return guarded(i.host, "coupling_jacobian", [&] {
          return i.object->coupling_jacobian(*eval, dR_dp, dR_dv, dF_dy, dF_dydot);
        });
      };
    } else {
      return nullptr;
    }
  }
  static EnergyOp energy_op() {
    if constexpr (detail::HasEnergy<T>::value) {
      return [](const mh_subsystem* s, const mh_subsystem_eval* eval, double* stored,
                double* dissipation) noexcept {
        Instance& i = self(s);
        return guarded(i.host, "energy",
                       [&] { return i.object->energy(*eval, *stored, *dissipation); });
      };
    } else {
      return nullptr;
    }
  }
  static AcceptOp accept_op() {
    if constexpr (detail::HasAccept<T>::value) {
      return [](const mh_subsystem* s, const mh_subsystem_eval* eval) noexcept {
        Instance& i = self(s);
        return guarded(i.host, "accept", [&] { return i.object->accept(*eval); });
      };
    } else {
      return nullptr;
    }
  }
  // parameters.h from T's kParameters (or parameter_count and
  // parameter_spec), parameter and set_parameter (cpp/parameters.hpp).
  static uint32_t parameter_count(const void* instance) {
    if constexpr (detail::HasParameters<T>::value) {
      (void)instance;
      return static_cast<uint32_t>(std::size(T::kParameters));
    } else {
      return static_cast<uint32_t>(object_of(instance).parameter_count());
    }
  }
  static ParameterSpec parameter_spec(const void* instance, uint32_t index) {
    if constexpr (detail::HasParameters<T>::value) {
      (void)instance;
      return T::kParameters[index];
    } else {
      return object_of(instance).parameter_spec(index);
    }
  }
  static const mh_parameters_extension* parameters_extension() noexcept {
    static const mh_parameters_extension ext{
        sizeof(mh_parameters_extension),
        [](const void* instance) noexcept { return parameter_count(instance); },
        [](const void* instance, uint32_t index, mh_parameter_info* info) noexcept {
          if (index >= parameter_count(instance) || info == nullptr) return MH_ERROR;
          const ParameterSpec p = parameter_spec(instance, index);
          info->key = p.key;
          info->unit = p.unit;
          info->lower = p.lower;
          info->upper = p.upper;
          return MH_OK;
        },
        [](const void* instance, uint32_t index, double* value) noexcept {
          if (index >= parameter_count(instance) || value == nullptr) return MH_ERROR;
          *value = object_of(instance).parameter(index);
          return MH_OK;
        },
        [](const void* instance, uint32_t index, double value) noexcept {
          const Instance& i = self(static_cast<const mh_subsystem*>(instance));
          if (index >= parameter_count(instance)) {
            detail::log_failure(i.host, "set parameter", "index out of range");
            return MH_ERROR;
          }
          const ParameterSpec p = parameter_spec(instance, index);
          if (!(value >= p.lower && value <= p.upper)) {
            detail::log_failure(
                i.host, p.key,
                (short_number(value) + " is outside the values it takes, [" +
                 short_number(p.lower) + ", " + short_number(p.upper) + "] " + p.unit)
                    .c_str());
            return MH_ERROR;
          }
          return guarded(i.host, p.key, [&] {
            i.object->set_parameter(index, value);
            return MH_OK;
          });
        }};
    return &ext;
  }
  static void destroy(const mh_subsystem* s) noexcept {
    delete static_cast<Instance*>(s->plugin_data);
  }
  static const void* get_extension(const mh_subsystem* s, const char* id) noexcept {
    if constexpr (detail::HasParameters<T>::value || detail::HasParameterList<T>::value) {
      if (id != nullptr && std::strcmp(id, MH_EXT_PARAMETERS) == 0) return parameters_extension();
    }
    if constexpr (detail::HasExtension<T>::value) {
      if (id == nullptr) return nullptr;
      try {
        return self(s).object->extension(id);
      } catch (...) {
        return nullptr;
      }
    } else {
      (void)s;
      (void)id;
      return nullptr;
    }
  }
};

template <class T>
constexpr SubsystemComponent subsystem_component() noexcept {
  if constexpr (detail::HasExampleModel<T>::value)
    return {&T::kDescriptor, &SubsystemAdapter<T>::create, T::kExampleModel};
  else
    return {&T::kDescriptor, &SubsystemAdapter<T>::create, nullptr};
}

// The mh_subsystem_factory over a fixed list of components (a static array
// that outlives the factory, e.g. one at namespace scope).
class SubsystemFactory {
 public:
  template <std::size_t N>
  constexpr explicit SubsystemFactory(const SubsystemComponent (&components)[N]) noexcept
      : api_{sizeof(mh_subsystem_factory), count, descriptor, create, example_model},
        components_(components),
        size_(static_cast<uint32_t>(N)) {}

  const mh_subsystem_factory* api() const noexcept { return &api_; }
  // For mh_plugin_entry.get_factory: this factory for MH_SUBSYSTEM_FACTORY_ID, else NULL.
  const void* get_factory(const char* factory_id) const noexcept {
    return factory_id != nullptr && std::strcmp(factory_id, MH_SUBSYSTEM_FACTORY_ID) == 0 ? &api_
                                                                                          : nullptr;
  }

 private:
  // The host holds &api_, which is this object's address (first member of a
  // standard-layout class): the operations below recover the object from it.
  mh_subsystem_factory api_;
  const SubsystemComponent* components_;
  uint32_t size_;

  static const SubsystemFactory& self(const mh_subsystem_factory* f) noexcept {
    return *reinterpret_cast<const SubsystemFactory*>(f);
  }
  static uint32_t count(const mh_subsystem_factory* f) noexcept { return self(f).size_; }
  static const mh_component_descriptor* descriptor(const mh_subsystem_factory* f,
                                                   uint32_t index) noexcept {
    const SubsystemFactory& factory = self(f);
    return index < factory.size_ ? factory.components_[index].descriptor : nullptr;
  }
  static const char* example_model(const mh_subsystem_factory* f, uint32_t index) noexcept {
    const SubsystemFactory& factory = self(f);
    return index < factory.size_ ? factory.components_[index].example_model : nullptr;
  }
  static const mh_subsystem* create(const mh_subsystem_factory* f, const mh_host* host,
                                    const char* id) noexcept {
    if (host == nullptr || id == nullptr) return nullptr;
    const SubsystemFactory& factory = self(f);
    for (uint32_t i = 0; i < factory.size_; ++i)
      if (std::strcmp(factory.components_[i].descriptor->id, id) == 0)
        return factory.components_[i].create(host);
    detail::log_failure(host, id, "no such component in this library");
    return nullptr;
  }
};
static_assert(std::is_standard_layout_v<SubsystemFactory>,
              "SubsystemFactory must be standard-layout: the host holds its first member");

}  // namespace monohydra

// Defines the library's entry symbol `mh_entry` (its only export) with one
// subsystem factory listing the given monohydra::SubsystemComponent values.
// Use once per library, at namespace scope of one source file.
#define MONOHYDRA_SUBSYSTEM_PLUGIN(...)                                                      \
  namespace {                                                                                \
  const ::monohydra::SubsystemComponent monohydra_plugin_components[] = {__VA_ARGS__};       \
  const ::monohydra::SubsystemFactory monohydra_plugin_factory(monohydra_plugin_components); \
  int monohydra_plugin_init(const char*) {                                                   \
    return 1;                                                                                \
  }                                                                                          \
  void monohydra_plugin_deinit() {}                                                          \
  const void* monohydra_plugin_get_factory(const char* id) {                                 \
    return monohydra_plugin_factory.get_factory(id);                                         \
  }                                                                                          \
  }                                                                                          \
  extern "C" MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry {                               \
    MH_ABI_VERSION_INIT, monohydra_plugin_init, monohydra_plugin_deinit,                     \
        monohydra_plugin_get_factory                                                         \
  }
