// The shared checks of common.hpp.
#include "common.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>

namespace integ {

mh_status fail(const Common& c, const char* op, const char* reason) noexcept {
  if (c.host != nullptr && c.host->log != nullptr) {
    char message[256];  // fixed: no allocation on the step's error paths
    std::snprintf(message, sizeof(message), "%s integrator, %s: %s", c.id, op, reason);
    c.host->log(c.host, MH_LOG_ERROR, message);
  }
  return MH_ERROR;
}

bool all_finite(const double* v, uint32_t n) noexcept {
  for (uint32_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

mh_status read_problem(Common& c, const mh_integrator_problem* problem) {
  c.set_up = false;
  c.restarted = false;
  c.step_open = false;
  if (problem == nullptr) return fail(c, "setup", "no problem given");
  // 3.0 fields, read only when the host's struct holds them (types.h).
  if (problem->struct_size < offsetof(mh_integrator_problem, dt) + sizeof(problem->dt))
    return fail(c, "setup", "the problem struct is too small for SDK 3.0");
  if (problem->num_unknowns > 0 && problem->kinds == nullptr)
    return fail(c, "setup", "no kinds given for the unknowns");
  if (!std::isfinite(problem->t0)) return fail(c, "setup", "t0 is not finite");
  if (!(problem->dt > 0.0) || !std::isfinite(problem->dt))
    return fail(c, "setup", "dt is not a positive finite number");
  for (uint32_t i = 0; i < problem->num_unknowns; ++i)
    if (problem->kinds[i] > MH_UNKNOWN_ALGEBRAIC)
      return fail(c, "setup", "an unknown has a kind that is not an mh_unknown_kind");
  c.n = problem->num_unknowns;
  c.kinds.assign(problem->kinds, problem->kinds + problem->num_unknowns);
  c.t = problem->t0;
  return MH_OK;
}

mh_status check_restart(const Common& c, const mh_unknown_values* at) noexcept {
  if (!c.set_up) return fail(c, "restart", "called before a successful setup");
  if (at == nullptr) return fail(c, "restart", "no values given");
  if (at->num_unknowns != c.n)
    return fail(c, "restart", "the values' num_unknowns is not the problem's");
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  if (!std::isfinite(at->t)) return fail(c, "restart", "t is not finite");
  if (c.n > 0 && (x == nullptr || xd == nullptr || xdd == nullptr))
    return fail(c, "restart", "x, xd or xdd is NULL");
  if (!all_finite(x, c.n) || !all_finite(xd, c.n) || !all_finite(xdd, c.n))
    return fail(c, "restart", "x, xd or xdd holds a value that is not finite");
  return MH_OK;
}

mh_status check_begin_step(const Common& c, double t_next, double h,
                           const mh_step_map* map) noexcept {
  if (!c.restarted) return fail(c, "begin_step", "called before restart");
  if (!(h > 0.0) || !std::isfinite(h)) return fail(c, "begin_step", "h is not a positive number");
  if (!std::isfinite(t_next)) return fail(c, "begin_step", "t_next is not finite");
  if (map == nullptr) return fail(c, "begin_step", "no map given");
  if (map->struct_size < offsetof(mh_step_map, xdd_offset) + sizeof(map->xdd_offset))
    return fail(c, "begin_step", "the map struct is too small for SDK 3.0");
  if (map->num_unknowns != c.n)
    return fail(c, "begin_step", "the map's num_unknowns is not the problem's");
  if (c.n > 0 &&
      (map->x_predicted == nullptr || map->xd_offset == nullptr || map->xdd_offset == nullptr))
    return fail(c, "begin_step", "x_predicted, xd_offset or xdd_offset is NULL");
  return MH_OK;
}

mh_status check_accept(const Common& c, const mh_unknown_values* at) noexcept {
  if (!c.step_open) return fail(c, "accept", "no step is open (begin_step was not called)");
  if (at == nullptr) return fail(c, "accept", "no values given");
  if (at->num_unknowns != c.n)
    return fail(c, "accept", "the values' num_unknowns is not the problem's");
  const double* x = at->x;
  const double* xd = at->xd;
  const double* xdd = at->xdd;
  if (!std::isfinite(at->t)) return fail(c, "accept", "t is not finite");
  if (c.n > 0 && (x == nullptr || xd == nullptr || xdd == nullptr))
    return fail(c, "accept", "x, xd or xdd is NULL");
  if (!all_finite(x, c.n) || !all_finite(xd, c.n) || !all_finite(xdd, c.n))
    return fail(c, "accept", "x, xd or xdd holds a value that is not finite");
  return MH_OK;
}

}  // namespace integ
