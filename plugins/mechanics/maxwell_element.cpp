// A Maxwell element between two body points: a spring k in series with a
// damper c. The damper's elongation delta is a state of the element, so it
// exercises states, body forces and their coupled tangent through the ABI:
//   tension   T = k (l - l0 - delta) = c ddelta/dt
//   residual  c ddelta/dt - k (l - l0 - delta) = 0   (row of delta)
#include <new>
#include <string>

#include "components.hpp"
#include "point_pair.hpp"

namespace mech {
namespace {

struct Maxwell {
  const mh_host* host = nullptr;
  double k = 0.0, c = 0.0, l0 = 0.0;
  int32_t a = -1, b = -1;
  int32_t delta = -1;  // global state index
};

Maxwell& self(const mh_subsystem* s) {
  return *static_cast<Maxwell*>(s->plugin_data);
}

mh_status setup(const mh_subsystem* s) {
  Maxwell& d = self(s);
  const mh_host* h = d.host;
  double delta0 = 0.0;
  mh_mech_info info{};
  info.struct_size = sizeof(info);
  if (h->mech_info(h, &info) != MH_OK) return MH_ERROR;
  double tol = info.position_tolerance;
  if (h->option_number(h, "stiffness", 1, 0.0, &d.k) != MH_OK ||
      h->option_number(h, "damping", 1, 0.0, &d.c) != MH_OK ||
      h->option_number(h, "free_length", 1, 0.0, &d.l0) != MH_OK ||
      h->option_number(h, "initial_elongation", 0, 0.0, &delta0) != MH_OK ||
      h->option_number(h, "tolerance", 0, tol, &tol) != MH_OK)
    return MH_ERROR;
  if (!(d.k > 0.0)) return h->option_error(h, "stiffness", "a positive stiffness (N/m)");
  if (!(d.c > 0.0)) return h->option_error(h, "damping", "a positive damping (N s/m)");
  if (d.l0 < 0.0) return h->option_error(h, "free_length", "a non-negative length (m)");
  if (!(tol > 0.0)) return h->option_error(h, "tolerance", "a positive tolerance (m)");
  if (h->add_point(h, "a", &d.a) != MH_OK || h->add_point(h, "b", &d.b) != MH_OK ||
      h->add_state(h, "delta", delta0, tol, "m", &d.delta) != MH_OK)
    return MH_ERROR;
  return MH_OK;
}

mh_status evaluate(const mh_subsystem* s, const mh_subsystem_eval* eval) {
  const Maxwell& d = self(s);
  PointPair pp;
  if (!pp.measure(eval)) {
    d.host->log(d.host, MH_LOG_ERROR, "the Maxwell element's points coincide: no direction");
    return MH_ERROR;
  }
  const double delta = eval->y[d.delta];
  const double tension = d.k * (pp.length - d.l0 - delta);
  eval->residual[d.delta] += d.c * eval->ydot[d.delta] - tension;
  pp.apply_tension(eval, tension);
  return MH_OK;
}

// Touched states: only delta, so 1 x 1 blocks.
mh_status jacobian(const mh_subsystem* s, const mh_subsystem_eval*, double* d_dy, double* d_dydot) {
  const Maxwell& d = self(s);
  d_dy[0] = d.k;
  d_dydot[0] = d.c;
  return MH_OK;
}

mh_status energy(const mh_subsystem* s, const mh_subsystem_eval* eval, double* stored,
                 double* dissipation) {
  const Maxwell& d = self(s);
  PointPair pp;
  if (!pp.measure(eval)) return MH_DISCARD;
  const double spring = pp.length - d.l0 - eval->y[d.delta];
  const double rate = eval->ydot[d.delta];
  *stored = 0.5 * d.k * spring * spring;
  *dissipation = d.c * rate * rate;
  return MH_OK;
}

void destroy(const mh_subsystem* s) {
  delete static_cast<Maxwell*>(s->plugin_data);
  delete s;
}

const void* get_extension(const mh_subsystem*, const char*) {
  return nullptr;
}

}  // namespace

const mh_component_descriptor kMaxwellDescriptor{
    sizeof(mh_component_descriptor),
    "maxwell",
    "Maxwell element",
    "monohydra",
    "1.0.0",
    "Spring in series with a damper between points a and b; state delta (m) is the damper's "
    "elongation. Options: stiffness (N/m), damping (N s/m), free_length (m), "
    "initial_elongation (m, default 0), tolerance (m)."};

const mh_subsystem* create_maxwell_element(const mh_host* host) {
  auto* d = new (std::nothrow) Maxwell;
  auto* s = new (std::nothrow) mh_subsystem{};
  if (d == nullptr || s == nullptr) {
    delete d;
    delete s;
    return nullptr;
  }
  d->host = host;
  s->struct_size = sizeof(mh_subsystem);
  s->descriptor = &kMaxwellDescriptor;
  s->plugin_data = d;
  s->setup = setup;
  s->evaluate = evaluate;
  s->jacobian = jacobian;
  s->energy = energy;
  s->accept = nullptr;
  s->destroy = destroy;
  s->get_extension = get_extension;
  return s;
}

}  // namespace mech
