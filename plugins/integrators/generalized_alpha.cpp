// The generalized-alpha method in the form of Arnold & Bruels (2007): an
// acceleration-like variable a, the equations enforced at t_{n+1}, and the
// Chung-Hulbert parameters from the spectral radius at infinity rho_inf.
// First-order unknowns take the first-order method of Jansen, Whiting &
// Hulbert (2000), written in the same form (docs/integrators.md).
#include <cmath>
#include <vector>

#include "common.hpp"
#include "integrators.hpp"
#include "monohydra/cpp/services.hpp"

namespace integ {
namespace {

struct GeneralizedAlpha : Common {
  double rho_inf = 0.8;
  // Second-order unknowns (Chung & Hulbert 1993, as Arnold & Bruels 2007 use them).
  double am = 0.0, af = 0.0, gamma = 0.5, beta = 0.25;
  // First-order unknowns (Jansen, Whiting & Hulbert 2000, weights on t_n as above).
  double am1 = 0.0, af1 = 0.0, gamma1 = 0.5;
  std::vector<double> x, xd, xdd, a;  // n: the history at t_n (a: acceleration-like,
                                      // or the rate-like variable of first-order unknowns)

  template <class Archive>
  void state(Archive& ar) {
    common_state(ar);
    ar(x);
    ar(xd);
    ar(xdd);
    ar(a);
  }
};

GeneralizedAlpha& self(const mh_integrator* s) {
  return *static_cast<GeneralizedAlpha*>(s->plugin_data);
}

mh_status setup(const mh_integrator* s, const mh_integrator_problem* problem) {
  GeneralizedAlpha& g = self(s);
  return monohydra::guarded_integrator_op(g.host, "generalized-alpha setup", [&] {
    if (read_problem(g, problem) != MH_OK) return MH_ERROR;
    const mh_host* host = g.host;
    if (monohydra::options(host).option_number(host, "rho_inf", 0, 0.8, &g.rho_inf) != MH_OK)
      return MH_ERROR;
    if (!(g.rho_inf >= 0.0 && g.rho_inf <= 1.0))
      return monohydra::options(host).option_error(host, "rho_inf",
                                                   "a spectral radius at infinity in [0, 1]");
    const double rho = g.rho_inf;
    g.am = (2.0 * rho - 1.0) / (rho + 1.0);             // alpha_m
    g.af = rho / (rho + 1.0);                           // alpha_f
    g.gamma = 0.5 - g.am + g.af;                        // second order
    g.beta = 0.25 * (g.gamma + 0.5) * (g.gamma + 0.5);  // beta = (gamma + 1/2)^2 / 4
    g.am1 = (3.0 * rho - 1.0) / (2.0 * (rho + 1.0));    // 1 - alpha_m of JWH
    g.af1 = rho / (rho + 1.0);                          // 1 - alpha_f of JWH
    g.gamma1 = 0.5 - g.am1 + g.af1;                     // = 1 / (1 + rho)
    for (std::vector<double>* v : {&g.x, &g.xd, &g.xdd, &g.a}) v->assign(g.n, 0.0);
    g.set_up = true;
    return MH_OK;
  });
}

mh_status restart(const mh_integrator* s, const mh_unknown_values* at) {
  GeneralizedAlpha& g = self(s);
  return monohydra::guarded_integrator_op(g.host, "generalized-alpha restart", [&] {
    if (check_restart(g, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    for (uint32_t i = 0; i < g.n; ++i) {
      g.x[i] = x[i];
      g.xd[i] = xd[i];
      g.xdd[i] = xdd[i];
      // a_0 = xdd_0 (second order), v_0 = xd_0 (first order).
      g.a[i] = g.kinds[i] == MH_UNKNOWN_FIRST_ORDER ? xd[i] : xdd[i];
    }
    g.t = t;
    g.restarted = true;
    g.step_open = false;
    return MH_OK;
  });
}

mh_status begin_step(const mh_integrator* s, double t_next, double h, mh_step_map* map) {
  GeneralizedAlpha& g = self(s);
  return monohydra::guarded_integrator_op(g.host, "generalized-alpha begin_step", [&] {
    if (check_begin_step(g, t_next, h, map) != MH_OK) return MH_ERROR;
    const double am = g.am, af = g.af, gamma = g.gamma, beta = g.beta;
    const double am1 = g.am1, af1 = g.af1, gamma1 = g.gamma1;
    const double h2 = h * h;
    mh_step_coefficients& c = map->coefficients;
    c.struct_size = sizeof(mh_step_coefficients);
    c.h = h;
    c.dxd_dx_second = gamma / (beta * h);                       // d xd_{n+1} / d x_{n+1}
    c.dxdd_dx_second = (1.0 - am) / ((1.0 - af) * beta * h2);   // d xdd_{n+1} / d x_{n+1}
    c.dxd_dx_first = (1.0 - am1) / ((1.0 - af1) * gamma1 * h);  // d yd_{n+1} / d y_{n+1}
    for (uint32_t i = 0; i < g.n; ++i) {
      const double x = g.x[i], xd = g.xd[i], xdd = g.xdd[i], a = g.a[i];
      switch (g.kinds[i]) {
        case MH_UNKNOWN_SECOND_ORDER: {
          // x_{n+1} = x_n + h xd_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1}
          //   => a_{n+1} = (x_{n+1} - xs) / (beta h^2), with
          const double xs = x + h * xd + (h2 * (0.5 - beta)) * a;
          // xd_{n+1} = xd_n + h (1 - gamma) a_n + h gamma a_{n+1}
          //          = gamma / (beta h) x_{n+1} + [xd_n + h (1 - gamma) a_n - gamma / (beta h) xs]
          map->xd_offset[i] = xd + (h * (1.0 - gamma)) * a - (gamma / (beta * h)) * xs;
          // (1 - af) xdd_{n+1} + af xdd_n = (1 - am) a_{n+1} + am a_n
          //   => xdd_{n+1} = (1 - am) / ((1 - af) beta h^2) x_{n+1}
          //                  + [am a_n - af xdd_n - (1 - am) / (beta h^2) xs] / (1 - af)
          map->xdd_offset[i] = (am * a - af * xdd - ((1.0 - am) / (beta * h2)) * xs) / (1.0 - af);
          // Predictor, constant a: a_{n+1} = a_n => x = x_n + h xd_n + h^2/2 a_n.
          map->x_predicted[i] = x + h * xd + (0.5 * h2) * a;
          break;
        }
        case MH_UNKNOWN_FIRST_ORDER: {
          // y_{n+1} = y_n + h (1 - gamma1) v_n + h gamma1 v_{n+1}
          //   => v_{n+1} = (y_{n+1} - ys) / (gamma1 h), with
          const double ys = x + (h * (1.0 - gamma1)) * a;
          // (1 - af1) yd_{n+1} + af1 yd_n = (1 - am1) v_{n+1} + am1 v_n
          //   => yd_{n+1} = (1 - am1) / ((1 - af1) gamma1 h) y_{n+1}
          //                 + [am1 v_n - af1 yd_n - (1 - am1) / (gamma1 h) ys] / (1 - af1)
          map->xd_offset[i] =
              (am1 * a - af1 * xd - ((1.0 - am1) / (gamma1 * h)) * ys) / (1.0 - af1);
          map->xdd_offset[i] = 0.0;         // no second rate
          map->x_predicted[i] = x + h * a;  // Predictor, constant v: v_{n+1} = v_n.
          break;
        }
        default:                    // algebraic: no rate
          map->x_predicted[i] = x;  // the last value
          map->xd_offset[i] = 0.0;
          map->xdd_offset[i] = 0.0;
          break;
      }
    }
    g.h = h;
    g.step_open = true;
    return MH_OK;
  });
}

mh_status accept(const mh_integrator* s, const mh_unknown_values* at) {
  GeneralizedAlpha& g = self(s);
  return monohydra::guarded_integrator_op(g.host, "generalized-alpha accept", [&] {
    if (check_accept(g, at) != MH_OK) return MH_ERROR;
    const double t = at->t;
    const double* x = at->x;
    const double* xd = at->xd;
    const double* xdd = at->xdd;
    for (uint32_t i = 0; i < g.n; ++i) {
      if (g.kinds[i] == MH_UNKNOWN_SECOND_ORDER)
        // (1 - am) a_{n+1} + am a_n = (1 - af) xdd_{n+1} + af xdd_n, from the accepted xdd.
        g.a[i] = ((1.0 - g.af) * xdd[i] + g.af * g.xdd[i] - g.am * g.a[i]) / (1.0 - g.am);
      else if (g.kinds[i] == MH_UNKNOWN_FIRST_ORDER)
        // (1 - am1) v_{n+1} + am1 v_n = (1 - af1) yd_{n+1} + af1 yd_n, from the accepted yd.
        g.a[i] = ((1.0 - g.af1) * xd[i] + g.af1 * g.xd[i] - g.am1 * g.a[i]) / (1.0 - g.am1);
      g.x[i] = x[i];
      g.xd[i] = xd[i];
      g.xdd[i] = xdd[i];
    }
    g.t = t;
    g.step_open = false;
    return MH_OK;
  });
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "generalized-alpha",
    "Generalized-alpha method",
    "monohydra",
    "1.0.0",
    "Arnold & Bruels' generalized-alpha (Chung-Hulbert parameters; Jansen-Whiting-Hulbert for "
    "first-order unknowns): second order, numerical dissipation set by the option rho_inf "
    "(spectral radius at infinity, default 0.8)."};

const mh_integrator kOps =
    implicit_ops<GeneralizedAlpha>(kDescriptor, setup, restart, begin_step, accept);

const mh_integrator* create(const mh_host* host) {
  return create_named<GeneralizedAlpha>(host, kOps);
}

}  // namespace

const monohydra::IntegratorComponent kGeneralizedAlpha{&kDescriptor, create};

}  // namespace integ
