// monohydra SDK, optional C++17 helper: the host's services (host.h) as
// references that are never NULL. `monohydra::options(host)` is the
// instance's options service, or, when its role has none, a table whose every
// call logs which service is missing and returns MH_ERROR, so a plugin's setup
// reads
//
//   if (monohydra::options(host).option_number(host, "k", 1, 0.0, &k) != MH_OK) ...
//
// Each call is a lookup by name (get_service): fine in create and setup; a
// call made in the time step (evaluate_mechanics) keeps the table found once,
// e.g. `const mh_mechanism_service* mech = &monohydra::mechanism(host);`.
#pragma once

#include <cstddef>
#include <cstdint>

#include "monohydra/host.h"

namespace monohydra {

namespace services_detail {

inline mh_status missing(const mh_host* host, const char* service) noexcept {
  if (host != nullptr && host->log != nullptr) host->log(host, MH_LOG_ERROR, service);
  return MH_ERROR;
}

template <class T>
const T* find(const mh_host* host, const char* id) noexcept {
  if (host == nullptr || host->get_service == nullptr) return nullptr;
  return static_cast<const T*>(host->get_service(host, id));
}

}  // namespace services_detail

inline const mh_options_service& options(const mh_host* host) noexcept {
  static const mh_options_service kMissing{
      sizeof(mh_options_service),
      [](const mh_host* h, const char*, int, double, double*) {
        return services_detail::missing(h, "this instance has no options service");
      },
      [](const mh_host* h, const char*, int, const char*, const char**) {
        return services_detail::missing(h, "this instance has no options service");
      },
      [](const mh_host* h, const char*, int, uint32_t, const double**, uint32_t*) {
        return services_detail::missing(h, "this instance has no options service");
      },
      [](const mh_host* h, const char*, const char*) {
        return services_detail::missing(h, "this instance has no options service");
      }};
  const auto* s = services_detail::find<mh_options_service>(host, MH_SERVICE_OPTIONS);
  return s != nullptr ? *s : kMissing;
}

inline const mh_mechanism_service& mechanism(const mh_host* host) noexcept {
  static const mh_mechanism_service kMissing{
      sizeof(mh_mechanism_service),
      [](const mh_host* h, mh_mech_info*) {
        return services_detail::missing(h, "this instance has no mechanism service");
      },
      [](const mh_host* h, const mh_mech_request*, mh_mech_result*) {
        return services_detail::missing(h, "this instance may not evaluate the mechanics");
      },
      [](const mh_host* h, const mh_mech_derivatives_request*, mh_mech_derivatives*) {
        return services_detail::missing(h, "this instance may not ask for mech_derivatives");
      }};
  // A subsystem's table gives mech_info alone (evaluate_mechanics and
  // mech_derivatives NULL): only a formulation evaluates the mechanics.
  const auto* s = services_detail::find<mh_mechanism_service>(host, MH_SERVICE_MECHANISM);
  return s != nullptr ? *s : kMissing;
}

// Whether the host gives this formulation mech_derivatives (a host of 3.0
// does; a table found missing refuses every call).
inline bool has_mech_derivatives(const mh_mechanism_service& mech) noexcept {
  return mech.struct_size >=
             offsetof(mh_mechanism_service, mech_derivatives) + sizeof(mech.mech_derivatives) &&
         mech.mech_derivatives != nullptr;
}

inline const mh_outputs_service& outputs(const mh_host* host) noexcept {
  static const mh_outputs_service kMissing{
      sizeof(mh_outputs_service), [](const mh_host* h, const mh_output_spec*, int32_t*) {
        return services_detail::missing(h, "this instance may not declare outputs");
      }};
  const auto* s = services_detail::find<mh_outputs_service>(host, MH_SERVICE_OUTPUTS);
  return s != nullptr ? *s : kMissing;
}

inline const mh_subsystem_setup_service& subsystem_setup(const mh_host* host) noexcept {
  static const mh_subsystem_setup_service kMissing{
      sizeof(mh_subsystem_setup_service),
      [](const mh_host* h, const mh_state_spec*, int32_t*) {
        return services_detail::missing(h, "only a subsystem declares states");
      },
      [](const mh_host* h, const char*, int32_t*) {
        return services_detail::missing(h, "only a subsystem finds states");
      },
      [](const mh_host* h, const char*, int32_t*) {
        return services_detail::missing(h, "only a subsystem attaches to points");
      },
      [](const mh_host* h, const mh_port_spec*, int32_t*) {
        return services_detail::missing(h, "only a subsystem declares ports");
      },
      [](const mh_host* h, int32_t, double*) {
        return services_detail::missing(h, "only a subsystem has points");
      },
      [](const mh_host* h, double) {
        return services_detail::missing(h, "only a subsystem declares time events");
      }};
  const auto* s =
      services_detail::find<mh_subsystem_setup_service>(host, MH_SERVICE_SUBSYSTEM_SETUP);
  return s != nullptr ? *s : kMissing;
}

// The signals service (3.1): a host of 3.0 has none, and the table found
// missing says so ("this host has no signals service (SDK 3.1)").
inline const mh_signals_service& signals(const mh_host* host) noexcept {
  static const mh_signals_service kMissing{
      sizeof(mh_signals_service),
      [](const mh_host* h, const char*, int, double, mh_signal*) {
        return services_detail::missing(
            h, "this host has no signals service (SDK 3.1): a subsystem reads signals from 3.1 on");
      },
      [](const mh_host* h, const char*, int, double, mh_signal*) {
        return services_detail::missing(
            h, "this host has no signals service (SDK 3.1): a subsystem reads signals from 3.1 on");
      }};
  const auto* s = services_detail::find<mh_signals_service>(host, MH_SERVICE_SIGNALS);
  return s != nullptr ? *s : kMissing;
}

// The option `key` as a signal input port (option_signal_port, 3.2): a table,
// an input or a state of the run. A host of 3.1 has no ports: there the
// option is read with option_signal (tables and inputs), so a component
// built against 3.2 still loads in a 3.1 host. out->state says which it got.
inline mh_status signal_port(const mh_host* host, const char* key, int required, double fallback,
                             mh_signal* out) noexcept {
  const mh_signals_service& s = signals(host);
  const bool has_port = s.struct_size >= offsetof(mh_signals_service, option_signal_port) +
                                             sizeof(s.option_signal_port) &&
                        s.option_signal_port != nullptr;
  if (out != nullptr) out->state = -1;
  return has_port ? s.option_signal_port(host, key, required, fallback, out)
                  : s.option_signal(host, key, required, fallback, out);
}

inline const mh_unknowns_service& unknowns(const mh_host* host) noexcept {
  static const mh_unknowns_service kMissing{
      sizeof(mh_unknowns_service), [](const mh_host* h, const mh_unknown_spec*, int32_t*) {
        return services_detail::missing(h, "only a formulation declares unknowns");
      }};
  const auto* s = services_detail::find<mh_unknowns_service>(host, MH_SERVICE_UNKNOWNS);
  return s != nullptr ? *s : kMissing;
}

}  // namespace monohydra
