// The trapezoidal rule with the unknowns at the step's end as primary
// variables, the paper's Eqs. (32)-(34): the default integrator. Its numbers
// are written exactly as the 1.x core and formulations wrote them, so results
// stay bit-close to theirs.
#include <vector>

#include "common.hpp"
#include "integrators.hpp"

namespace integ {
namespace {

struct Trapezoidal : Common {
  std::vector<double> x, xd, xdd;  // n: the history at t_k

  template <class Archive>
  void state(Archive& a) {
    common_state(a);
    a(x);
    a(xd);
    a(xdd);
  }
};

Trapezoidal& self(const mh_integrator* s) {
  return *static_cast<Trapezoidal*>(s->plugin_data);
}

mh_status setup(const mh_integrator* s, const mh_integrator_problem* problem) {
  Trapezoidal& z = self(s);
  return monohydra::guarded_integrator_op(z.host, "trapezoidal setup", [&] {
    if (read_problem(z, problem) != MH_OK) return MH_ERROR;
    for (std::vector<double>* v : {&z.x, &z.xd, &z.xdd}) v->assign(z.n, 0.0);
    z.set_up = true;
    return MH_OK;
  });
}

mh_status restart(const mh_integrator* s, const mh_unknown_values* at) {
  Trapezoidal& z = self(s);
  return monohydra::guarded_integrator_op(z.host, "trapezoidal restart", [&] {
    if (check_restart(z, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    for (uint32_t i = 0; i < z.n; ++i) {
      z.x[i] = x[i];
      z.xd[i] = xd[i];
      z.xdd[i] = xdd[i];
    }
    z.t = t;
    z.restarted = true;
    z.step_open = false;
    return MH_OK;
  });
}

mh_status begin_step(const mh_integrator* s, double t_next, double h, mh_step_map* map) {
  Trapezoidal& z = self(s);
  return monohydra::guarded_integrator_op(z.host, "trapezoidal begin_step", [&] {
    if (check_begin_step(z, t_next, h, map) != MH_OK) return MH_ERROR;
    const double dt = h;
    mh_step_coefficients& c = map->coefficients;
    c.struct_size = sizeof(mh_step_coefficients);
    c.h = dt;
    c.dxd_dx_second = 2.0 / dt;          // Eq. (33): zd_{k+1} = (2/dt) z_{k+1} + zd_hat
    c.dxdd_dx_second = 4.0 / (dt * dt);  // Eq. (33): zdd_{k+1} = (4/dt^2) z_{k+1} + zdd_hat
    c.dxd_dx_first = 2.0 / dt;           // Eq. (33): pd_{k+1} = (2/dt) p_{k+1} + p_hat
    for (uint32_t i = 0; i < z.n; ++i) {
      switch (z.kinds[i]) {
        case MH_UNKNOWN_SECOND_ORDER:
          // After Eq. (34): z_{k+1} = z_k + dt zd_k + dt^2/2 zdd_k.
          map->x_predicted[i] = z.x[i] + dt * z.xd[i] + (0.5 * dt * dt) * z.xdd[i];
          // Eq. (34): zd_hat = -((2/dt) z_k + zd_k).
          map->xd_offset[i] = -((2.0 / dt) * z.x[i] + z.xd[i]);
          // Eq. (34): zdd_hat = -((4/dt^2) z_k + (4/dt) zd_k + zdd_k).
          map->xdd_offset[i] = -((4.0 / (dt * dt)) * z.x[i] + (4.0 / dt) * z.xd[i] + z.xdd[i]);
          break;
        case MH_UNKNOWN_FIRST_ORDER:
          map->x_predicted[i] = z.x[i] + dt * z.xd[i];  // After Eq. (34): p_{k+1} = p_k + dt pd_k.
          map->xd_offset[i] = -((2.0 / dt) * z.x[i] + z.xd[i]);  // Eq. (34): p_hat.
          map->xdd_offset[i] = 0.0;                              // no second rate
          break;
        default:                         // algebraic: no rate
          map->x_predicted[i] = z.x[i];  // the last value
          map->xd_offset[i] = 0.0;
          map->xdd_offset[i] = 0.0;
          break;
      }
    }
    z.h = dt;
    z.step_open = true;
    return MH_OK;
  });
}

mh_status accept(const mh_integrator* s, const mh_unknown_values* at) {
  Trapezoidal& z = self(s);
  return monohydra::guarded_integrator_op(z.host, "trapezoidal accept", [&] {
    if (check_accept(z, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    // The history of the next step's Eq. (34) is the accepted state.
    for (uint32_t i = 0; i < z.n; ++i) {
      z.x[i] = x[i];
      z.xd[i] = xd[i];
      z.xdd[i] = xdd[i];
    }
    z.t = t;
    z.step_open = false;
    return MH_OK;
  });
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "trapezoidal",
    "Trapezoidal rule",
    "monohydra",
    "1.0.0",
    "The implicit trapezoidal rule with positions and pressures as primary unknowns (Eqs. "
    "32-34): second order, A-stable, no numerical dissipation."};

const mh_integrator kOps =
    implicit_ops<Trapezoidal>(kDescriptor, setup, restart, begin_step, accept);

const mh_integrator* create(const mh_host* host) {
  return create_named<Trapezoidal>(host, kOps);
}

}  // namespace

const monohydra::IntegratorComponent kTrapezoidal{&kDescriptor, create};

}  // namespace integ
