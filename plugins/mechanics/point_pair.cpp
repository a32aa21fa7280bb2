#include "point_pair.hpp"

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

}  // namespace mech
