// BDF2 with variable steps, applied to x for xd and again to xd for xdd of
// second-order unknowns (which is BDF2 on the first-order form x' = v,
// v' = ...). The first step after a restart is BDF1 (backward Euler) on both
// levels, since the history then holds one point only.
#include <vector>

#include "common.hpp"
#include "integrators.hpp"

namespace integ {
namespace {

struct Bdf2 : Common {
  std::vector<double> x, xd, xdd;  // n: the history at t_n
  std::vector<double> x1, xd1;     // n: at t_{n-1}
  double h_prev = 0.0;             // t_n - t_{n-1}
  bool two_points = false;         // t_{n-1} is in the history (false right after a restart)

  template <class Archive>
  void state(Archive& a) {
    common_state(a);
    a(x);
    a(xd);
    a(xdd);
    a(x1);
    a(xd1);
    a(h_prev);
    a(two_points);
  }
};

Bdf2& self(const mh_integrator* s) {
  return *static_cast<Bdf2*>(s->plugin_data);
}

mh_status setup(const mh_integrator* s, const mh_integrator_problem* problem) {
  Bdf2& b = self(s);
  return monohydra::guarded_integrator_op(b.host, "bdf2 setup", [&] {
    if (read_problem(b, problem) != MH_OK) return MH_ERROR;
    for (std::vector<double>* v : {&b.x, &b.xd, &b.xdd, &b.x1, &b.xd1}) v->assign(b.n, 0.0);
    b.two_points = false;
    b.set_up = true;
    return MH_OK;
  });
}

mh_status restart(const mh_integrator* s, const mh_unknown_values* at) {
  Bdf2& b = self(s);
  return monohydra::guarded_integrator_op(b.host, "bdf2 restart", [&] {
    if (check_restart(b, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    for (uint32_t i = 0; i < b.n; ++i) {
      b.x[i] = x[i];
      b.xd[i] = xd[i];
      b.xdd[i] = xdd[i];
    }
    b.two_points = false;  // the next step is BDF1: only the given state is used
    b.t = t;
    b.restarted = true;
    b.step_open = false;
    return MH_OK;
  });
}

mh_status begin_step(const mh_integrator* s, double t_next, double h, mh_step_map* map) {
  Bdf2& b = self(s);
  return monohydra::guarded_integrator_op(b.host, "bdf2 begin_step", [&] {
    if (check_begin_step(b, t_next, h, map) != MH_OK) return MH_ERROR;
    // xd_{n+1} = c0 x_{n+1} + c1 x_n + c2 x_{n-1}. Variable-step BDF2, w = h / h_prev:
    //   c0 = (1 + 2w) / ((1 + w) h), c1 = -(1 + w) / h, c2 = w^2 / ((1 + w) h)
    // (w = 1: (3 x_{n+1} - 4 x_n + x_{n-1}) / (2h)); BDF1: c0 = 1/h, c1 = -1/h, c2 = 0.
    double c0 = 1.0 / h, c1 = -1.0 / h, c2 = 0.0;
    if (b.two_points) {
      const double w = h / b.h_prev;
      c0 = (1.0 + 2.0 * w) / ((1.0 + w) * h);
      c1 = -(1.0 + w) / h;
      c2 = (w * w) / ((1.0 + w) * h);
    }
    mh_step_coefficients& c = map->coefficients;
    c.struct_size = sizeof(mh_step_coefficients);
    c.h = h;
    c.dxd_dx_second = c0;
    c.dxdd_dx_second = c0 * c0;  // xdd = c0 xd + ... and xd = c0 x + ...
    c.dxd_dx_first = c0;
    for (uint32_t i = 0; i < b.n; ++i) {
      switch (b.kinds[i]) {
        case MH_UNKNOWN_SECOND_ORDER: {
          // xd_{n+1} = c0 x_{n+1} + (c1 x_n + c2 x_{n-1})
          const double xd_offset = c1 * b.x[i] + c2 * b.x1[i];
          map->xd_offset[i] = xd_offset;
          // xdd_{n+1} = c0 xd_{n+1} + c1 xd_n + c2 xd_{n-1}
          //           = c0^2 x_{n+1} + (c0 xd_offset + c1 xd_n + c2 xd_{n-1})
          map->xdd_offset[i] = c0 * xd_offset + c1 * b.xd[i] + c2 * b.xd1[i];
          // Predictor: the quadratic Taylor extrapolation x_n + h xd_n + h^2/2 xdd_n.
          map->x_predicted[i] = b.x[i] + h * b.xd[i] + (0.5 * h * h) * b.xdd[i];
          break;
        }
        case MH_UNKNOWN_FIRST_ORDER:
          map->xd_offset[i] = c1 * b.x[i] + c2 * b.x1[i];  // yd_{n+1} = c0 y_{n+1} + offset
          map->xdd_offset[i] = 0.0;                        // no second rate
          map->x_predicted[i] = b.x[i] + h * b.xd[i];      // Predictor: y_n + h yd_n.
          break;
        default:                         // algebraic: no rate
          map->x_predicted[i] = b.x[i];  // the last value
          map->xd_offset[i] = 0.0;
          map->xdd_offset[i] = 0.0;
          break;
      }
    }
    b.h = h;
    b.step_open = true;
    return MH_OK;
  });
}

mh_status accept(const mh_integrator* s, const mh_unknown_values* at) {
  Bdf2& b = self(s);
  return monohydra::guarded_integrator_op(b.host, "bdf2 accept", [&] {
    if (check_accept(b, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    // Shift the history: (t_{n-1}, t_n) <- (t_n, t_{n+1}); t_{n+1} - t_n is the open step's h.
    for (uint32_t i = 0; i < b.n; ++i) {
      b.x1[i] = b.x[i];
      b.xd1[i] = b.xd[i];
      b.x[i] = x[i];
      b.xd[i] = xd[i];
      b.xdd[i] = xdd[i];
    }
    b.h_prev = b.h;
    b.two_points = true;
    b.t = t;
    b.step_open = false;
    return MH_OK;
  });
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "bdf2",
    "BDF2 (variable step)",
    "monohydra",
    "1.0.0",
    "The two-step backward differentiation formula with variable-step coefficients, on x and "
    "again on xd: second order, L-stable (strong damping of stiff components); backward Euler "
    "on the first step after a restart."};

const mh_integrator kOps = implicit_ops<Bdf2>(kDescriptor, setup, restart, begin_step, accept);

const mh_integrator* create(const mh_host* host) {
  return create_named<Bdf2>(host, kOps);
}

}  // namespace

const monohydra::IntegratorComponent kBdf2{&kDescriptor, create};

}  // namespace integ
