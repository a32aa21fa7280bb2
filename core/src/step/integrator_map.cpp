// The host's side of the integrator (integrator.h): the step's affine map
// from the Newton unknowns x at the step's end to their rates, applied to
// every unknown alike, mechanical or not. For the trapezoidal rule this is
// Eq. (33) with the hats of Eq. (34) as offsets.
#include "engine.hpp"
#include "monohydra/cpp/unknowns.hpp"

namespace mh {

void Simulation::Engine::begin_step(double t_next, double h) {
  work.map_ws.map.struct_size = sizeof(work.map_ws.map);
  work.map_ws.map.num_unknowns = static_cast<uint32_t>(n);
  work.map_ws.map.coefficients.struct_size = sizeof(work.map_ws.map.coefficients);
  work.map_ws.map.x_predicted = work.map_ws.x_pred.data();
  work.map_ws.map.xd_offset = work.map_ws.xd_off.data();
  work.map_ws.map.xdd_offset = work.map_ws.xdd_off.data();
  check(in_flight(*integrator_host, InstanceHost::Op::begin_step,
                  [&] {
                    return integrator.ops.begin_step(integrator.self, t_next, h, &work.map_ws.map);
                  }),
        "integrator", integrator_name, "begin_step");
  const mh_step_coefficients& c = work.map_ws.map.coefficients;
  const double coefficients[3] = {c.dxd_dx_second, c.dxdd_dx_second, c.dxd_dx_first};
  check_finite(coefficients, 3, *integrator_host, "begin_step",
               "the map's coefficients (dxd_dx_second, dxdd_dx_second, dxd_dx_first)");
  const auto count = static_cast<size_t>(n);
  check_finite(work.map_ws.x_pred.data(), count, *integrator_host, "begin_step", "x_predicted");
  check_finite(work.map_ws.xd_off.data(), count, *integrator_host, "begin_step", "xd_offset");
  check_finite(work.map_ws.xdd_off.data(), count, *integrator_host, "begin_step", "xdd_offset");
}

void Simulation::Engine::rates_of(const Eigen::VectorXd& xq, Eigen::VectorXd& xdq,
                                  Eigen::VectorXd& xddq) const {
  const mh_step_coefficients& c = work.map_ws.map.coefficients;
  for (int i = 0; i < n; ++i) {
    switch (registry.kinds[static_cast<size_t>(i)]) {
      case MH_UNKNOWN_SECOND_ORDER:
        xdq[i] = c.dxd_dx_second * xq[i] + work.map_ws.xd_off[i];     // Eq. (33), zd
        xddq[i] = c.dxdd_dx_second * xq[i] + work.map_ws.xdd_off[i];  // Eq. (33), zdd
        break;
      case MH_UNKNOWN_FIRST_ORDER:
        xdq[i] = c.dxd_dx_first * xq[i] + work.map_ws.xd_off[i];  // Eq. (33), ydot
        xddq[i] = 0.0;
        break;
      default:  // algebraic: no rate
        xdq[i] = 0.0;
        xddq[i] = 0.0;
        break;
    }
  }
}

void Simulation::Engine::restart_integrator() {
  check(in_flight(*integrator_host, InstanceHost::Op::restart,
                  [&] {
                    const mh_unknown_values at =
                        monohydra::unknown_values(run.accepted.t, static_cast<size_t>(n),
                                                  run.x.data(), run.xd.data(), run.xdd.data());
                    return integrator.ops.restart(integrator.self, &at);
                  }),
        "integrator", integrator_name, "restart");
  run.stability_due = explicit_method;  // a new start: its stability is checked again
}

}  // namespace mh
