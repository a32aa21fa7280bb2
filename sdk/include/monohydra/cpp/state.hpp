// monohydra SDK, optional C++17 helper: the state extension (state.h) from one
// list of members. A plugin's state type T whose plugin_data is a T* (what
// create_formulation and create_integrator make) lists what it keeps between
// steps once,
//
//   template <class Archive> void state(Archive& a) { a(t_k); a(z); a(lambda_k); }
//
// and returns monohydra::state_extension<mh_formulation, T>() from its
// get_extension for MH_EXT_STATE. The same list sizes, saves and loads, so the
// three cannot disagree. A member is a number (any arithmetic type) or a
// contiguous container of numbers (std::vector, an Eigen vector or matrix:
// anything with data() and size()) whose length setup fixed: only the
// elements travel, and load refuses bytes of another length. After a load,
// T's `std::string state_loaded()` runs when T has one: it refactors what
// depends on the state, drops caches, and returns "" or why the bytes are not
// a state of this instance (an index out of range); then the state before the
// load is put back and load fails with that reason.
#ifndef MONOHYDRA_CPP_STATE_HPP
#define MONOHYDRA_CPP_STATE_HPP

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "monohydra/cpp/guarded.hpp"
#include "monohydra/state.h"

namespace monohydra {

namespace state_detail {

template <class T, class = void>
struct IsContiguous : std::false_type {};
template <class T>
struct IsContiguous<
    T, std::void_t<decltype(std::declval<T&>().data()), decltype(std::declval<T&>().size())>>
    : std::is_arithmetic<
          std::remove_cv_t<std::remove_reference_t<decltype(*std::declval<T&>().data())>>> {};

template <class T, class = void>
struct HasLoaded : std::false_type {};
template <class T>
struct HasLoaded<T, std::void_t<decltype(std::declval<T&>().state_loaded())>> : std::true_type {};

// The bytes of one member, and where they are.
template <class V>
std::pair<void*, uint64_t> bytes_of(V& v) {
  if constexpr (std::is_arithmetic_v<V>) {
    return {&v, sizeof(V)};
  } else {
    static_assert(IsContiguous<V>::value,
                  "a state member is a number or a contiguous container of numbers");
    using E = std::remove_reference_t<decltype(*v.data())>;
    return {static_cast<void*>(v.data()), static_cast<uint64_t>(v.size()) * sizeof(E)};
  }
}

}  // namespace state_detail

// Counts the bytes of the members it is shown.
struct StateSizer {
  uint64_t bytes = 0;
  template <class V>
  void operator()(V& v) {
    bytes += state_detail::bytes_of(v).second;
  }
};

// Copies the members into a buffer of the counted size.
struct StateWriter {
  unsigned char* at;
  template <class V>
  void operator()(V& v) {
    const auto [p, n] = state_detail::bytes_of(v);
    if (n > 0) std::memcpy(at, p, n);
    at += n;
  }
};

// Copies a buffer of the counted size into the members.
struct StateReader {
  const unsigned char* at;
  template <class V>
  void operator()(V& v) {
    const auto [p, n] = state_detail::bytes_of(v);
    if (n > 0) std::memcpy(p, at, n);
    at += n;
  }
};

// The state extension of instances whose table type is Table (mh_formulation,
// mh_integrator) and whose plugin_data is a T* with a state(Archive&) member.
template <class Table, class T>
const mh_state_extension* state_extension() noexcept {
  struct Ops {
    static T& of(const void* instance) {
      return *static_cast<T*>(static_cast<const Table*>(instance)->plugin_data);
    }
    static uint64_t size(const void* instance) noexcept {
      if (instance == nullptr) return 0;
      StateSizer sizer;
      of(instance).state(sizer);
      return sizer.bytes;
    }
    static mh_status save(const void* instance, void* bytes, uint64_t n) noexcept {
      if (instance == nullptr) return MH_ERROR;
      T& s = of(instance);
      return guarded(s.host, "saving the state", [&] {
        if (bytes == nullptr || n != size(instance)) return refuse(s, "save", n, size(instance));
        StateWriter writer{static_cast<unsigned char*>(bytes)};
        s.state(writer);
        return MH_OK;
      });
    }
    static mh_status load(const void* instance, const void* bytes, uint64_t n) noexcept {
      if (instance == nullptr) return MH_ERROR;
      T& s = of(instance);
      return guarded(s.host, "loading the state", [&] {
        if (bytes == nullptr || n != size(instance)) return refuse(s, "load", n, size(instance));
        if constexpr (state_detail::HasLoaded<T>::value) {
          std::vector<unsigned char> before(static_cast<size_t>(n));
          StateWriter keep{before.data()};
          s.state(keep);
          StateReader reader{static_cast<const unsigned char*>(bytes)};
          s.state(reader);
          const std::string refused = s.state_loaded();
          if (refused.empty()) return MH_OK;
          StateReader back{before.data()};
          s.state(back);
          (void)s.state_loaded();
          return fail(s, ("load of the state: " + refused).c_str());
        } else {
          StateReader reader{static_cast<const unsigned char*>(bytes)};
          s.state(reader);
          return MH_OK;
        }
      });
    }
    static mh_status refuse(const T& s, const char* op, uint64_t given, uint64_t own) {
      return fail(s, (std::string(op) + " of the state: " +
                      (given == own ? std::string("no buffer")
                                    : std::to_string(given) + " bytes given, " +
                                          std::to_string(own) + " expected"))
                         .c_str());
    }
    static mh_status fail(const T& s, const char* message) {
      if (s.host != nullptr && s.host->log != nullptr) s.host->log(s.host, MH_LOG_ERROR, message);
      return MH_ERROR;
    }
  };
  static const mh_state_extension table{sizeof(mh_state_extension), Ops::size, Ops::save,
                                        Ops::load};
  return &table;
}

}  // namespace monohydra

#endif  // MONOHYDRA_CPP_STATE_HPP
