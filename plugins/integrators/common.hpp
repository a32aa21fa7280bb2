// What every integrator of this library shares: the problem it was set up
// for, where it is in the host's protocol (setup -> restart -> [begin_step ->
// accept]*), and the checks of the host's arguments. Nothing here allocates
// after setup; failures are logged as "<integrator> <op>: <reason>".
#pragma once

#include <cstdint>
#include <vector>

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
};

// Logs "<id> <op>: <reason>" at error level; returns MH_ERROR.
mh_status fail(const Common& c, const char* op, const char* reason) noexcept;

// True when all n values are finite.
bool all_finite(const double* v, uint32_t n) noexcept;

// setup: checks the problem (struct size, n, kinds, t0, dt) and sizes `kinds`.
mh_status read_problem(Common& c, const mh_integrator_problem* problem);

// restart: checks t and the state (non-NULL, finite).
mh_status check_restart(const Common& c, double t, const double* x, const double* xd,
                        const double* xdd) noexcept;

// begin_step: checks the protocol, t_next and h (> 0, finite) and the map.
mh_status check_begin_step(const Common& c, double t_next, double h,
                           const mh_step_map* map) noexcept;

// accept: checks that a step is open and the accepted state (non-NULL, finite).
mh_status check_accept(const Common& c, double t, const double* x, const double* xd,
                       const double* xdd) noexcept;

}  // namespace integ
