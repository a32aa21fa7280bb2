// The host service mech_derivatives: K = d(M' zdd - Q')/dz and
// C = -dQ'/dzd with every subsystem force included, and the constraint
// terms' derivatives, from the core's analytic recursions
// (dynamics_derivatives.cpp, constraint_derivatives.cpp). A subsystem's
// point forces enter through their derivatives with respect to its points'
// motion: its point_force_jacobian when it gives one, else forward
// central differences of its evaluate in the point positions and velocities
// alone (one instance at a time, states held), which is cheap: 12P
// evaluations of one instance, never of the mechanics.
#include <algorithm>
#include <cmath>
#include <utility>

#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

void Simulation::Engine::size_derivatives() {
  work.derivs.dyn_ws = std::make_unique<DynamicsDerivativesWorkspace>(model);
  work.derivs.con_ws = std::make_unique<ConstraintDerivativesWorkspace>(model);
  size_t terms = 0;
  for (auto& s : subsystems) {
    const size_t P = s.points.size();
    terms += P * P;
    s.dF_dp.assign(9 * P * P, 0.0);
    s.dF_dv.assign(9 * P * P, 0.0);
    s.p_pert.assign(3 * P, 0.0);
    s.v_pert.assign(3 * P, 0.0);
    s.f_base.assign(3 * P, 0.0);
  }
  work.derivs.force_terms.assign(terms, PointForceTerm{});
  for (Eigen::MatrixXd* M : {&work.derivs.K, &work.derivs.C, &work.derivs.dPhizT_v_dz})
    M->setZero(N, N);
  // K and C are zeroed here and written by dynamics_derivatives alone, with
  // the same force terms every call: it need not zero them again (O(N^2)).
  work.derivs.dyn_ws->zero_unrelated = false;
  work.derivs.dA_dz.setZero(m, N);
  work.derivs.dA_dzd.setZero(m, N);
  work.derivs.saved_outputs.setZero(n_o);
  work.derivs.rows_discard.setZero(n_s);
  work.derivs.zdd_eval.setZero(N);
  work.derivs.v_eval.setZero(m);
}

namespace {

// dF/dp and dF/dv of instance s by central differences of its evaluate at
// the points' current p, v (in s.p, s.v) with the states held; its base forces
// in s.f_base. The rows it adds go to `ev`'s residual, a scratch buffer.
mh_status differenced_point_forces(SubsystemInstance& s, mh_subsystem_eval ev) {
  const size_t n3 = 3 * s.points.size();
  std::copy(s.p.begin(), s.p.end(), s.p_pert.begin());
  std::copy(s.v.begin(), s.v.end(), s.v_pert.begin());
  ev.num_points = static_cast<uint32_t>(s.points.size());
  ev.num_touched = static_cast<uint32_t>(s.touched.size());
  ev.point_p = s.p_pert.data();
  ev.point_v = s.v_pert.data();
  ev.point_f = s.f.data();
  std::copy(s.f.begin(), s.f.end(), s.f_base.begin());  // the forces at p, v themselves
  for (int level = 0; level < 2; ++level) {
    std::vector<double>& x = level == 0 ? s.p_pert : s.v_pert;
    GuardedArray& out = level == 0 ? s.dF_dp : s.dF_dv;
    for (size_t c = 0; c < n3; ++c) {
      const double x0 = x[c];
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      for (int side = 0; side < 2; ++side) {
        x[c] = side == 0 ? x0 + h : x0 - h;
        std::fill(s.f.begin(), s.f.end(), 0.0);
        const mh_status st = normalized(evaluate_instance(s, ev));
        if (!status_ok(st)) {
          x[c] = x0;
          return st;
        }
        const double sign = side == 0 ? 1.0 : -1.0;
        for (size_t r = 0; r < n3; ++r)
          out[c * n3 + r] = (side == 0 ? 0.0 : out[c * n3 + r]) + sign * s.f[r] / (2.0 * h);
      }
      x[c] = x0;
    }
  }
  std::copy(s.f_base.begin(), s.f_base.end(), s.f.begin());
  return MH_OK;
}

}  // namespace

// K or C is not finite: the point-force derivatives a plugin gave are
// searched for the writer (differenced ones come from finite forces).
mh_status Simulation::Engine::refuse_nonfinite_derivatives() {
  reports.last_plugin_error = "the mechanics' derivatives K, C are not finite";
  for (const SubsystemInstance& s : subsystems) {
    if (s.points.empty() || s.api.ops.point_force_jacobian == nullptr) continue;
    const std::pair<const GuardedArray*, const char*> given[] = {{&s.dF_dp, "dF_dp"},
                                                                 {&s.dF_dv, "dF_dv"}};
    for (const auto& [buffer, name] : given) {
      const size_t i = first_nonfinite(buffer->data(), buffer->size());
      if (i == buffer->size()) continue;
      reports.last_plugin_error =
          nonfinite_reason((*buffer)[i], i, *s.host, "point_force_jacobian", name);
      return MH_ERROR;
    }
  }
  return MH_ERROR;
}

// K and C where they can be non-zero: the mechanical pattern of coordinate
// unknowns (zero elsewhere, never written), else every entry.
bool Simulation::Engine::derivatives_finite() const {
  if (!work.tangent_ws.coordinate_unknowns)
    return all_finite(work.derivs.K.data(), static_cast<size_t>(work.derivs.K.size())) &&
           all_finite(work.derivs.C.data(), static_cast<size_t>(work.derivs.C.size()));
  const auto& start = work.tangent_ws.mech_column_start;
  const auto& rows = work.tangent_ws.mech_row_index;
  for (int c = 0; c + 1 < static_cast<int>(start.size()); ++c)
    for (int32_t k = start[static_cast<size_t>(c)]; k < start[static_cast<size_t>(c) + 1]; ++k) {
      const int row = rows[static_cast<size_t>(k)];
      if (!std::isfinite(work.derivs.K(row, c)) || !std::isfinite(work.derivs.C(row, c)))
        return false;
    }
  return true;
}

mh_status Simulation::Engine::mechanics_derivatives(const mh_mech_derivatives_request& rq) {
  kinematics_at(rq.z, rq.zd);
  if ((rq.flags & MH_DERIV_DYNAMICS) != 0) {
    ++run.counters.derivative_passes;
    // The subsystems at this motion, their states held: forces and their
    // derivatives. Outputs are restored after: they stay the iterate's.
    work.derivs.saved_outputs = registry.outputs;
    const double saved_power = work.eval.power;
    reset_applied_forces(model, data);
    mh_status st = evaluate_subsystems(rq.t, work.derivs.rows_discard.data());
    if (!status_ok(st)) return st;
    size_t term = 0;
    mh_subsystem_eval ev = subsystem_eval(rq.t, work.derivs.rows_discard.data());
    for (auto& s : subsystems) {
      const size_t P = s.points.size();
      if (P == 0) continue;
      const size_t n3 = 3 * P;
      if (s.api.ops.point_force_jacobian != nullptr) {
        std::fill(s.dF_dp.begin(), s.dF_dp.end(), 0.0);
        std::fill(s.dF_dv.begin(), s.dF_dv.end(), 0.0);
        point_at(ev, s);
        st = normalized(in_flight(*s.host, InstanceHost::Op::point_force_jacobian, [&] {
          return s.api.ops.point_force_jacobian(s.api.self, &ev, s.dF_dp.data(), s.dF_dv.data());
        }));
        check_guards(*s.host, "point_force_jacobian", {{&s.dF_dp, "dF_dp"}, {&s.dF_dv, "dF_dv"}});
        if (status_ok(st)) apply_planted(planted, s, 6, {&s.dF_dp, &s.dF_dv});
      } else {
        st = differenced_point_forces(s, ev);
      }
      if (!status_ok(st)) return st;
      // One term per (point a, point b): F_a once (with b = a), and the
      // dependence of F_a on point b's motion.
      for (size_t a = 0; a < P; ++a) {
        for (size_t b = 0; b < P; ++b) {
          PointForceTerm& ft = work.derivs.force_terms[term++];
          ft.point = s.points[a];
          ft.other = s.points[b];
          ft.F_W = a == b ? Eigen::Vector3d(s.f[3 * a], s.f[3 * a + 1], s.f[3 * a + 2])
                          : Eigen::Vector3d::Zero();
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const size_t at =
                  (3 * b + static_cast<size_t>(j)) * n3 + 3 * a + static_cast<size_t>(i);
              if (a == b) {
                ft.dF_dp(i, j) = s.dF_dp[at];
                ft.dF_dv(i, j) = s.dF_dv[at];
                ft.dF_dp_other(i, j) = 0.0;
                ft.dF_dv_other(i, j) = 0.0;
              } else {
                ft.dF_dp(i, j) = 0.0;
                ft.dF_dv(i, j) = 0.0;
                ft.dF_dp_other(i, j) = s.dF_dp[at];
                ft.dF_dv_other(i, j) = s.dF_dv[at];
              }
            }
        }
      }
    }
    registry.outputs = work.derivs.saved_outputs;
    work.eval.power = saved_power;
    work.derivs.zdd_eval = Eigen::Map<const Eigen::VectorXd>(rq.zdd, N);
    dynamics_derivatives(model, data, work.derivs.zdd_eval, work.derivs.force_terms,
                         *work.derivs.dyn_ws, work.derivs.K, work.derivs.C);
    if (!derivatives_finite()) return refuse_nonfinite_derivatives();
  }
  if ((rq.flags & MH_DERIV_CONSTRAINT_FORCES) != 0 && m > 0) {
    work.derivs.v_eval = Eigen::Map<const Eigen::VectorXd>(rq.v, m);
    constraint_force_derivative(model, data, cons.constraints, work.derivs.v_eval,
                                *work.derivs.con_ws, work.derivs.dPhizT_v_dz);
  }
  if ((rq.flags & MH_DERIV_CONSTRAINT_ACCELERATIONS) != 0 && m > 0) {
    work.derivs.zdd_eval = Eigen::Map<const Eigen::VectorXd>(rq.zdd, N);
    constraint_acceleration_derivatives(model, data, cons.constraints, work.derivs.zdd_eval,
                                        *work.derivs.con_ws, work.derivs.dA_dz, work.derivs.dA_dzd);
  }
  return MH_OK;
}

}  // namespace mh
