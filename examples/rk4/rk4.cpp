// The classical explicit fourth-order Runge-Kutta method (Kutta 1901) as a
// monohydra integrator (an explicit method, mh_explicit_method): the integrator the
// double-step method is usually run with. For the state X = (x, xd) of
// second-order unknowns and x of first-order ones, with the host's rates
// F(t, X) = (xd, xdd) and xd:
//   K_s = F(t + c_s h, X_k + a_s h K_{s-1}),  c = a = (0, 1/2, 1/2, 1),
//   X_{k+1} = X_k + h/6 (K_0 + 2 K_1 + 2 K_2 + K_3).
// Algebraic unknowns are not integrated: each stage starts from the host's
// last solution for them. Stable for h*lambda on the real axis down to
// -2.785 and on the imaginary axis up to 2.83 (docs/integrators.md): the stiff
// pressures of a hydraulic circuit need a far shorter step than an implicit
// rule.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "monohydra/cpp/integrator_plugin.hpp"
#include "monohydra/cpp/state.hpp"
#include "monohydra/integrator.h"

namespace rk4 {
namespace {

constexpr uint32_t kStages = 4;
constexpr double kStageFraction[kStages] = {0.0, 0.5, 0.5, 1.0};  // a_s = c_s
constexpr double kWeight[kStages] = {1.0 / 6.0, 2.0 / 6.0, 2.0 / 6.0, 1.0 / 6.0};

struct Rk4 {
  const mh_host* host = nullptr;
  uint32_t n = 0;
  std::vector<uint8_t> kinds;
  double t = 0.0;                 // the time of x, xd below
  bool restarted = false;         // a state exists
  std::vector<double> x, xd;      // n: the accepted state
  std::vector<double> algebraic;  // n: the host's last solution of algebraic unknowns
  std::vector<double> kx, kv;     // kStages x n: the stages' rates of x and of xd

  // What the next step reads (MH_EXT_STATE, monohydra/cpp/state.hpp): the
  // stages' rates are the step's own, not state.
  template <class Archive>
  void state(Archive& a) {
    a(t);
    a(restarted);
    a(x);
    a(xd);
    a(algebraic);
  }
};

Rk4& self(const mh_integrator* s) {
  return *static_cast<Rk4*>(s->plugin_data);
}

mh_status fail(const Rk4& r, const std::string& reason) {
  if (r.host != nullptr && r.host->log != nullptr)
    r.host->log(r.host, MH_LOG_ERROR, ("rk4 " + reason).c_str());
  return MH_ERROR;
}

mh_status setup(const mh_integrator* s, const mh_integrator_problem* problem) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 setup", [&] {
    if (problem == nullptr || problem->struct_size < sizeof(mh_integrator_problem))
      return fail(r, "setup: the host gave no problem, or one of an older SDK");
    if (problem->num_unknowns > 0 && problem->kinds == nullptr)
      return fail(r, "setup: the host gave no kinds of unknowns");
    r.n = problem->num_unknowns;
    r.kinds.assign(problem->kinds, problem->kinds + r.n);
    for (std::vector<double>* v : {&r.x, &r.xd, &r.algebraic}) v->assign(r.n, 0.0);
    r.kx.assign(size_t{kStages} * r.n, 0.0);
    r.kv.assign(size_t{kStages} * r.n, 0.0);
    return MH_OK;
  });
}

// The accepted (or restarted) state the next step starts from.
mh_status take_state(Rk4& r, double t, const double* x, const double* xd) {
  if (x == nullptr || xd == nullptr) return fail(r, "the host gave no state");
  for (uint32_t i = 0; i < r.n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(xd[i]))
      return fail(r, "the state of unknown " + std::to_string(i) + " is not finite");
    r.x[i] = x[i];
    r.xd[i] = xd[i];
    r.algebraic[i] = x[i];
  }
  r.t = t;
  r.restarted = true;
  return MH_OK;
}

mh_status restart(const mh_integrator* s, const mh_unknown_values* at) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 restart", [&] {
    if (at == nullptr || at->num_unknowns != r.n)
      return fail(r, "restart: no values, or not of the problem's length");
    return take_state(r, at->t, at->x, at->xd);
  });
}

mh_status accept(const mh_integrator* s, const mh_unknown_values* accepted) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 accept", [&] {
    if (accepted == nullptr || accepted->num_unknowns != r.n)
      return fail(r, "accept: no values, or not of the problem's length");
    return take_state(r, accepted->t, accepted->x, accepted->xd);
  });
}

// X_k + a h K_{s-1} (X_k at stage 0).
mh_status stage_state(const mh_integrator* s, uint32_t stage, double h, double* t_stage,
                      const mh_unknown_buffers* out) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 stage_state", [&] {
    if (!r.restarted) return fail(r, "stage_state: no restart since setup");
    if (stage >= kStages || t_stage == nullptr || out == nullptr || out->num_unknowns != r.n ||
        out->x == nullptr || out->xd == nullptr || !(h > 0.0))
      return fail(r, "stage_state: bad arguments (stage " + std::to_string(stage) + ")");
    double* x = out->x;
    double* xd = out->xd;
    const double ah = kStageFraction[stage] * h;
    const double* kx = stage == 0 ? nullptr : &r.kx[size_t{stage - 1} * r.n];
    const double* kv = stage == 0 ? nullptr : &r.kv[size_t{stage - 1} * r.n];
    for (uint32_t i = 0; i < r.n; ++i) {
      switch (r.kinds[i]) {
        case MH_UNKNOWN_SECOND_ORDER:
          x[i] = r.x[i] + (kx != nullptr ? ah * kx[i] : 0.0);
          xd[i] = r.xd[i] + (kv != nullptr ? ah * kv[i] : 0.0);
          break;
        case MH_UNKNOWN_FIRST_ORDER:
          x[i] = r.x[i] + (kx != nullptr ? ah * kx[i] : 0.0);
          break;
        default:  // algebraic: the host's last solution as its guess
          x[i] = r.algebraic[i];
          break;
      }
    }
    *t_stage = r.t + ah;
    return MH_OK;
  });
}

mh_status stage_rates(const mh_integrator* s, uint32_t stage, const mh_unknown_values* solved) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 stage_rates", [&] {
    if (stage >= kStages || solved == nullptr || solved->num_unknowns != r.n ||
        solved->x == nullptr || solved->xd == nullptr || solved->xdd == nullptr)
      return fail(r, "stage_rates: bad arguments (stage " + std::to_string(stage) + ")");
    const double* x = solved->x;
    const double* xd = solved->xd;
    const double* xdd = solved->xdd;
    double* kx = &r.kx[size_t{stage} * r.n];
    double* kv = &r.kv[size_t{stage} * r.n];
    for (uint32_t i = 0; i < r.n; ++i) {
      kx[i] = xd[i];
      kv[i] = r.kinds[i] == MH_UNKNOWN_SECOND_ORDER ? xdd[i] : 0.0;
      if (r.kinds[i] == MH_UNKNOWN_ALGEBRAIC) r.algebraic[i] = x[i];
    }
    return MH_OK;
  });
}

// X_{k+1} = X_k + h/6 (K_0 + 2 K_1 + 2 K_2 + K_3).
mh_status finish_step(const mh_integrator* s, double h, const mh_unknown_buffers* out) {
  Rk4& r = self(s);
  return monohydra::guarded_integrator_op(r.host, "rk4 finish_step", [&] {
    if (!r.restarted || out == nullptr || out->num_unknowns != r.n || out->x == nullptr ||
        out->xd == nullptr || !(h > 0.0))
      return fail(r, "finish_step: bad arguments or no restart since setup");
    double* x = out->x;
    double* xd = out->xd;
    for (uint32_t i = 0; i < r.n; ++i) {
      double dx = 0.0;
      double dv = 0.0;
      for (uint32_t k = 0; k < kStages; ++k) {
        dx += kWeight[k] * r.kx[size_t{k} * r.n + i];
        dv += kWeight[k] * r.kv[size_t{k} * r.n + i];
      }
      switch (r.kinds[i]) {
        case MH_UNKNOWN_SECOND_ORDER:
          x[i] = r.x[i] + h * dx;
          xd[i] = r.xd[i] + h * dv;
          break;
        case MH_UNKNOWN_FIRST_ORDER:
          x[i] = r.x[i] + h * dx;
          break;
        default:
          x[i] = r.algebraic[i];
          break;
      }
    }
    return MH_OK;
  });
}

const mh_component_descriptor kDescriptor{
    sizeof(mh_component_descriptor),
    "rk4",
    "Classical Runge-Kutta (explicit, 4th order)",
    "monohydra examples",
    "1.0.0",
    "Explicit 4-stage Runge-Kutta on the host's rates; stable only while |h lambda| < 2.78"};

// Its explicit method's own operations (integrator.h).
const mh_explicit_method kStagesOps{sizeof(mh_explicit_method), kStages, stage_state, stage_rates,
                                    finish_step};

mh_integrator make_ops() {
  mh_integrator f{};
  f.struct_size = sizeof(mh_integrator);
  f.descriptor = &kDescriptor;
  f.setup = setup;
  f.restart = restart;
  f.begin_step = nullptr;  // explicit: the host never asks for a map
  f.accept = accept;
  f.destroy = monohydra::destroy_integrator<Rk4>;
  f.get_extension = [](const mh_integrator*, const char* id) -> const void* {
    if (id != nullptr && std::strcmp(id, MH_EXT_STATE) == 0)
      return monohydra::state_extension<mh_integrator, Rk4>();  // snapshots of the run
    return nullptr;
  };
  f.explicit_method = &kStagesOps;
  return f;
}
const mh_integrator kOps = make_ops();

const mh_integrator* create(const mh_host* host) {
  return monohydra::create_integrator<Rk4>(host, kOps);
}
const monohydra::IntegratorComponent kRk4{&kDescriptor, create};

}  // namespace
}  // namespace rk4

MONOHYDRA_INTEGRATOR_PLUGIN(rk4::kRk4);
