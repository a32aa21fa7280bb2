// A linear spring and a linear damper in parallel between two body points:
// tension T = k (l - l0) + c ldot. No states: its only coupling to the Newton
// step is the force it applies to the bodies.
#include <new>
#include <string>

#include "components.hpp"
#include "point_pair.hpp"

namespace mech {
namespace {

struct SpringDamper {
  const mh_host* host = nullptr;
  double k = 0.0, c = 0.0, l0 = 0.0;
  int32_t a = -1, b = -1;
};

SpringDamper& self(const mh_subsystem* s) {
  return *static_cast<SpringDamper*>(s->plugin_data);
}

mh_status fail(const SpringDamper& d, const char* what) {
  d.host->log(d.host, MH_LOG_ERROR, what);
  return MH_ERROR;
}

mh_status setup(const mh_subsystem* s) {
  SpringDamper& d = self(s);
  const mh_host* h = d.host;
  if (h->option_number(h, "stiffness", 1, 0.0, &d.k) != MH_OK ||
      h->option_number(h, "damping", 0, 0.0, &d.c) != MH_OK ||
      h->option_number(h, "free_length", 1, 0.0, &d.l0) != MH_OK)
    return MH_ERROR;
  if (d.k < 0.0) return h->option_error(h, "stiffness", "a non-negative stiffness (N/m)");
  if (d.c < 0.0) return h->option_error(h, "damping", "a non-negative damping (N s/m)");
  if (d.l0 < 0.0) return h->option_error(h, "free_length", "a non-negative length (m)");
  if (h->add_point(h, "a", &d.a) != MH_OK || h->add_point(h, "b", &d.b) != MH_OK) return MH_ERROR;
  return MH_OK;
}

mh_status evaluate(const mh_subsystem* s, const mh_subsystem_eval* eval) {
  const SpringDamper& d = self(s);
  PointPair pp;
  if (!pp.measure(eval)) return fail(d, "the spring-damper's points coincide: no direction");
  pp.apply_tension(eval, d.k * (pp.length - d.l0) + d.c * pp.rate);
  return MH_OK;
}

mh_status energy(const mh_subsystem* s, const mh_subsystem_eval* eval, double* stored,
                 double* dissipation) {
  const SpringDamper& d = self(s);
  PointPair pp;
  if (!pp.measure(eval)) return MH_DISCARD;
  const double stretch = pp.length - d.l0;
  *stored = 0.5 * d.k * stretch * stretch;
  *dissipation = d.c * pp.rate * pp.rate;
  return MH_OK;
}

void destroy(const mh_subsystem* s) {
  delete static_cast<SpringDamper*>(s->plugin_data);
  delete s;
}

const void* get_extension(const mh_subsystem*, const char*) {
  return nullptr;
}

}  // namespace

const mh_component_descriptor kSpringDamperDescriptor{
    sizeof(mh_component_descriptor),
    "spring-damper",
    "Linear spring-damper",
    "monohydra",
    "1.0.0",
    "Spring and damper in parallel between points a and b: tension k (l - l0) + c dl/dt. "
    "Options: stiffness (N/m), damping (N s/m, default 0), free_length (m)."};

const mh_subsystem* create_spring_damper(const mh_host* host) {
  auto* d = new (std::nothrow) SpringDamper;
  auto* s = new (std::nothrow) mh_subsystem{};
  if (d == nullptr || s == nullptr) {
    delete d;
    delete s;
    return nullptr;
  }
  d->host = host;
  s->struct_size = sizeof(mh_subsystem);
  s->descriptor = &kSpringDamperDescriptor;
  s->plugin_data = d;
  s->setup = setup;
  s->evaluate = evaluate;
  s->jacobian = nullptr;  // no states: nothing to differentiate
  s->energy = energy;
  s->accept = nullptr;
  s->destroy = destroy;
  s->get_extension = get_extension;
  return s;
}

}  // namespace mech
