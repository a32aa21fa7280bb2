#include "point_pair.hpp"

#include "monohydra/visual.h"

namespace mech {

bool PointPair::measure(const mh_subsystem_eval* eval) {
  const double* pa = eval->point_p;
  const double* pb = eval->point_p + 3;
  const double* va = eval->point_v;
  const double* vb = eval->point_v + 3;
  double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(length > 1e-12)) return false;
  rate = 0.0;
  for (int i = 0; i < 3; ++i) {
    e[i] = d[i] / length;
    rate += (vb[i] - va[i]) * e[i];
  }
  return true;
}

void PointPair::apply_tension(const mh_subsystem_eval* eval, double tension) const {
  for (int i = 0; i < 3; ++i) {
    eval->point_f[i] += tension * e[i];
    eval->point_f[3 + i] -= tension * e[i];
  }
}

void PointPair::rate_gradient(const mh_subsystem_eval* eval, double* drate_dpb) const {
  const double* va = eval->point_v;
  const double* vb = eval->point_v + 3;
  for (int j = 0; j < 3; ++j) {
    drate_dpb[j] = 0.0;
    for (int i = 0; i < 3; ++i)
      drate_dpb[j] += (vb[i] - va[i]) * ((i == j ? 1.0 : 0.0) - e[i] * e[j]) / length;
  }
}

void PointPair::tension_jacobian(const mh_subsystem_eval* eval, double tension, double dT_dl,
                                 double dT_drate, double* dF_dp, double* dF_dv) const {
  double drate[3];
  rate_gradient(eval, drate);
  for (int force_point = 0; force_point < 2; ++force_point) {
    const double fs = force_point == 0 ? 1.0 : -1.0;  // +T e on a, -T e on b
    for (int moved = 0; moved < 2; ++moved) {
      const double ms = moved == 0 ? -1.0 : 1.0;  // d/dp_a = -d/dp_b
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const int at = (3 * moved + j) * 6 + 3 * force_point + i;
          const double de = ((i == j ? 1.0 : 0.0) - e[i] * e[j]) / length;
          dF_dp[at] += fs * ms * (e[i] * (dT_dl * e[j] + dT_drate * drate[j]) + tension * de);
          dF_dv[at] += fs * ms * e[i] * dT_drate * e[j];
        }
    }
  }
}

mh_status declare_link(const mh_host* host, int32_t point_a, int32_t point_b) {
  const auto* visual =
      static_cast<const mh_visual_service*>(host->get_service(host, MH_SERVICE_VISUAL));
  if (visual == nullptr) return MH_OK;
  mh_visual_spec look{};
  look.struct_size = sizeof(mh_visual_spec);
  look.kind = MH_VISUAL_LINK;
  look.point_a = point_a;
  look.point_b = point_b;
  look.rod_diameter = 0.02;  // m: a thin line on a machine's scale
  look.state_a = -1;
  look.state_b = -1;
  return visual->add_visual(host, &look);
}

}  // namespace mech
