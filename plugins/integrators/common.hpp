// What every integrator of this library shares: the problem it was set up
// for, where it is in the host's protocol (setup -> restart -> [begin_step ->
// accept]*), and the checks of the host's arguments. Nothing here allocates
// after setup; failures are logged as "<integrator> <op>: <reason>".
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "monohydra/cpp/integrator_plugin.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/integrator.h"

namespace integ {

struct Common {
  const mh_host* host = nullptr;
  const char* id = "";         // the integrator's id, for messages
  uint32_t n = 0;              // number of unknowns
  std::vector<uint8_t> kinds;  // n: mh_unknown_kind of each unknown
  bool set_up = false;         // setup succeeded
  bool restarted = false;      // a history exists (restart called since setup)
  bool step_open = false;      // begin_step called since the last restart or accept
  double t = 0.0;              // the time of the history (last restart or accept)
  double h = 0.0;              // the open step's h

  // The protocol's part of the state (MH_EXT_STATE): saved between steps,
  // so no step is open after a load.
  template <class Archive>
  void common_state(Archive& a) {
    a(t);
    a(restarted);
  }
  std::string state_loaded() {
    step_open = false;
    return "";
  }
};

// Logs "<id> <op>: <reason>" at error level; returns MH_ERROR.
mh_status fail(const Common& c, const char* op, const char* reason) noexcept;

// True when all n values are finite.
bool all_finite(const double* v, uint32_t n) noexcept;

// setup: checks the problem (struct size, n, kinds, t0, dt) and sizes `kinds`.
mh_status read_problem(Common& c, const mh_integrator_problem* problem);

// restart: checks t and the state (given, of the problem's length, non-NULL, finite).
mh_status check_restart(const Common& c, const mh_unknown_values* at) noexcept;

// begin_step: checks the protocol, t_next and h (> 0, finite) and the map.
mh_status check_begin_step(const Common& c, double t_next, double h,
                           const mh_step_map* map) noexcept;

// accept: checks that a step is open and the accepted state (given, of the
// problem's length, non-NULL, finite).
mh_status check_accept(const Common& c, const mh_unknown_values* at) noexcept;

// The operations of an implicit integrator T (its state derives from Common):
// the same table for every integrator of this library but for its four ops.
template <class T>
mh_integrator implicit_ops(const mh_component_descriptor& descriptor,
                           decltype(mh_integrator::setup) setup,
                           decltype(mh_integrator::restart) restart,
                           decltype(mh_integrator::begin_step) begin_step,
                           decltype(mh_integrator::accept) accept) {
  mh_integrator f{};
  f.struct_size = sizeof(mh_integrator);
  f.descriptor = &descriptor;
  f.setup = setup;
  f.restart = restart;
  f.begin_step = begin_step;
  f.accept = accept;
  f.destroy = monohydra::destroy_integrator<T>;
  // Every integrator here saves and loads its history (T::state).
  f.get_extension = [](const mh_integrator*, const char* id) -> const void* {
    if (id != nullptr && std::strcmp(id, MH_EXT_STATE) == 0)
      return monohydra::state_extension<mh_integrator, T>();
    return nullptr;
  };
  return f;
}

// A new instance of T with the ops, named after its descriptor in messages.
template <class T>
const mh_integrator* create_named(const mh_host* host, const mh_integrator& ops) {
  const mh_integrator* made = monohydra::create_integrator<T>(host, ops);
  if (made != nullptr) static_cast<T*>(made->plugin_data)->id = ops.descriptor->id;
  return made;
}

}  // namespace integ
