// The tangent's coupling of the subsystems with points to the mechanical
// unknowns without differencing the mechanics: when the formulation
// says how its mechanics depended on x (mechanics_map: dz/dx, dzd/dx, dzd/dxd
// and dr/dQ'), then, in the state columns and in the mechanical columns its
// tangent gave (the host differences the others whole),
//   d(state rows)/dx = dR/dp dp/dz dz/dx + dR/dv (dv/dz dz/dx + dv/dzd dzd/dx)
//   d(mechanical rows)/dy = dr/dQ' sum_points J_p^T dF/dy
// (Eq. 10: a point force F enters Q' as J_p^T F). The instance's own
// derivatives in its points' motion and its states come from its
// coupling_jacobian, else from central differences of its evaluate
// alone (one instance, never the mechanics); the
// point Jacobians from the kinematics of the iterate (motion_variation.hpp).
#include <algorithm>
#include <cmath>

#include "algorithms/motion_variation.hpp"
#include "engine.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {

void Simulation::Engine::size_coupling() {
  work.coupling.coupling_possible = formulation.ops.mechanics_map != nullptr && n_m > 0;
  for (const auto& s : subsystems) {
    if (s.points.empty()) continue;
    for (int a : s.touched)
      if (work.tangent_ws.column_analytic[static_cast<size_t>(a)] == 0)
        work.coupling.coupling_possible = false;
  }
  for (Eigen::MatrixXd* M : {&work.coupling.map_dz_dx, &work.coupling.map_dzd_dx,
                             &work.coupling.map_dzd_dxd, &work.coupling.map_dzd_total})
    M->setZero(N, n_m);
  work.coupling.map_dr_dQ.setZero(n_m, N);
  work.coupling.point_jp.setZero(3, N);
  work.coupling.point_jv.setZero(3, N);
  work.coupling.point_dp_dx.setZero(3, n_m);
  work.coupling.point_dv_dx.setZero(3, n_m);
  work.coupling.dr_dF.setZero(n_m, 3);
  for (Eigen::VectorXd* v : {&work.eval.z_iterate, &work.eval.zd_iterate, &work.tangent_ws.z_base,
                             &work.tangent_ws.zd_base, &work.eval.kin_z, &work.eval.kin_zd})
    v->setZero(N);
  for (auto& s : subsystems) {
    const size_t k = s.touched.size();
    const size_t n3 = 3 * s.points.size();
    s.dR_dp.assign(k * n3, 0.0);
    s.dR_dv.assign(k * n3, 0.0);
    s.dF_dy.assign(n3 * k, 0.0);
    s.dF_dydot.assign(n3 * k, 0.0);
    s.rows_in_mech.assign(s.points.empty() ? 0 : k * static_cast<size_t>(n_m), -1);
    s.mech_in_cols.assign(s.points.empty() ? 0 : k * static_cast<size_t>(n_m), -1);
    if (s.points.empty()) continue;
    for (size_t a = 0; a < k; ++a)
      for (int c = 0; c < n_m; ++c) {
        const size_t at = a * static_cast<size_t>(n_m) + static_cast<size_t>(c);
        s.rows_in_mech[at] = work.tangent_ws.pattern->slot(n_m + s.touched[a], c);
        s.mech_in_cols[at] = work.tangent_ws.pattern->slot(c, n_m + s.touched[a]);
      }
  }
}

namespace {

// dR/dp, dR/dv (k x 3P, column-major: row a = touched state a) and dF/dy
// (3P x k, column b = d/dy_b + cv_b d/dydot_b) of instance s by central
// differences of its evaluate at the points' motion in s.p, s.v and the states
// y, ydot (held and restored). Rows go to `rows`, a scratch buffer of n_s.
mh_status difference_instance(SubsystemInstance& s, mh_subsystem_eval ev, Eigen::VectorXd& y,
                              Eigen::VectorXd& ydot, const std::vector<char>& algebraic,
                              double dydot_dy, Eigen::VectorXd& rows) {
  const size_t n3 = 3 * s.points.size();
  const size_t k = s.touched.size();
  std::copy(s.p.begin(), s.p.end(), s.p_pert.begin());
  std::copy(s.v.begin(), s.v.end(), s.v_pert.begin());
  ev.num_points = static_cast<uint32_t>(s.points.size());
  ev.num_touched = static_cast<uint32_t>(s.touched.size());
  ev.point_p = s.p_pert.data();
  ev.point_v = s.v_pert.data();
  ev.point_f = s.f.data();
  ev.residual = rows.data();
  const auto run = [&]() {
    rows.setZero();
    std::fill(s.f.begin(), s.f.end(), 0.0);
    return normalized(evaluate_instance(s, ev));
  };
  // The points' motion: columns of dR/dp and dR/dv.
  for (int level = 0; level < 2; ++level) {
    std::vector<double>& x = level == 0 ? s.p_pert : s.v_pert;
    GuardedArray& out = level == 0 ? s.dR_dp : s.dR_dv;
    for (size_t c = 0; c < n3; ++c) {
      const double x0 = x[c];
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      for (int side = 0; side < 2; ++side) {
        x[c] = side == 0 ? x0 + h : x0 - h;
        const mh_status st = run();
        x[c] = x0;
        if (!status_ok(st)) return st;
        const double w = (side == 0 ? 1.0 : -1.0) / (2.0 * h);
        for (size_t a = 0; a < k; ++a) {
          double& o = out[c * k + a];
          o = (side == 0 ? 0.0 : o) + w * rows[s.touched[a]];
        }
      }
    }
  }
  // The states: columns of dF/dy along the integrator's map (Eq. 33).
  for (size_t b = 0; b < k; ++b) {
    const int i = s.touched[b];
    const double cv = algebraic[static_cast<size_t>(i)] != 0 ? 0.0 : dydot_dy;
    const double y0 = y[i], yd0 = ydot[i];
    const double h = 1e-6 * std::max(1.0, std::abs(y0));
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? 1.0 : -1.0;
      y[i] = y0 + sign * h;
      ydot[i] = yd0 + sign * cv * h;
      const mh_status st = run();
      y[i] = y0;
      ydot[i] = yd0;
      if (!status_ok(st)) return st;
      for (size_t r = 0; r < n3; ++r) {
        double& o = s.dF_dy[b * n3 + r];
        o = (side == 0 ? 0.0 : o) + sign * s.f[r] / (2.0 * h);
      }
    }
  }
  return MH_OK;
}

// dv/dz (3 x N) of a point: for z_k on its path, the point moves by b_k at p
// and its body's twist changes by b_k x (Z_e - Z_k) (motion_variation.hpp).
void point_velocity_jacobian(const Model& model, const Data& data, const BodyPoint& point,
                             const Eigen::Vector3d& p,
                             Eigen::Ref<Eigen::Matrix<double, 3, Eigen::Dynamic>> Jv) {
  Jv.setZero();
  const int e = point.body;
  if (e == kGround) return;
  const Eigen::Vector3d omega = data.Z[e].tail<3>();
  for (int k = e; k != kGround; k = model.bodies[k].parent) {
    const Eigen::Vector3d dp = detail::twist_at(data.b[k], p);
    const Vector6d dZ = detail::motion_cross(data.b[k], Vector6d(data.Z[e] - data.Z[k]));
    Jv.col(k) = detail::twist_at(dZ, p) + omega.cross(dp);
  }
}

}  // namespace

// How the formulation's mechanics depended on x at the last residual call
// (the iterate), and where that iterate's kinematics were.
mh_status Simulation::Engine::read_mechanics_map() {
  for (Eigen::MatrixXd* M : {&work.coupling.map_dz_dx, &work.coupling.map_dzd_dx,
                             &work.coupling.map_dzd_dxd, &work.coupling.map_dr_dQ})
    M->setZero();
  work.tangent_ws.z_base = work.eval.z_iterate;
  work.tangent_ws.zd_base = work.eval.zd_iterate;
  // The coordinates' derivatives serve only the mechanical columns the
  // formulation's tangent gave: without one, the formulation need not compute them.
  bool any_given = false;
  for (uint8_t g : work.tangent_ws.mech_column_given) any_given = any_given || g != 0;
  return normalized(in_flight(*formulation_host, InstanceHost::Op::mechanics_map, [&] {
    const mh_mechanics_map map{sizeof(mh_mechanics_map),
                               static_cast<uint32_t>(N),
                               static_cast<uint32_t>(n_m),
                               any_given ? work.coupling.map_dz_dx.data() : nullptr,
                               any_given ? work.coupling.map_dzd_dx.data() : nullptr,
                               any_given ? work.coupling.map_dzd_dxd.data() : nullptr,
                               work.coupling.map_dr_dQ.data()};
    return formulation.ops.mechanics_map(formulation.self, &map);
  }));
}

mh_status Simulation::Engine::couple_subsystems(double t_eval) {
  mh_status st = MH_OK;
  const mh_step_coefficients& cf = work.map_ws.map.coefficients;
  for (int c = 0; c < n_m; ++c) {
    const uint8_t kind = registry.kinds[static_cast<size_t>(c)];
    const double cv = kind == MH_UNKNOWN_SECOND_ORDER  ? cf.dxd_dx_second
                      : kind == MH_UNKNOWN_FIRST_ORDER ? cf.dxd_dx_first
                                                       : 0.0;
    work.coupling.map_dzd_total.col(c) =
        work.coupling.map_dzd_dx.col(c) + cv * work.coupling.map_dzd_dxd.col(c);
  }
  // The kinematics of the iterate (the formulation's tangent may have left
  // them there already).
  kinematics_at(work.tangent_ws.z_base.data(), work.tangent_ws.zd_base.data());
  // Zero the coupling entries; instances that share a state add to them. The
  // mechanical columns the host differenced hold their whole columns already.
  for (const auto& s : subsystems) {
    if (s.points.empty()) continue;
    // Outside the pattern (a coordinate that moves none of its points) the
    // entries are structurally zero and have no slot.
    for (size_t e = 0; e < s.rows_in_mech.size(); ++e) {
      const int below = s.rows_in_mech[e];
      if (below < 0) continue;
      if (work.tangent_ws.mech_column_given[e % static_cast<size_t>(n_m)] != 0)
        work.tangent_ws.values[static_cast<size_t>(below)] = 0.0;
      work.tangent_ws.values[static_cast<size_t>(s.mech_in_cols[e])] = 0.0;
    }
  }
  work.derivs.saved_outputs = registry.outputs;
  const double dydot_dy = cf.dxd_dx_first;
  mh_subsystem_eval ev = subsystem_eval(t_eval, work.derivs.rows_discard.data());
  for (auto& s : subsystems) {
    const size_t P = s.points.size();
    if (P == 0) continue;
    const size_t n3 = 3 * P;
    const size_t k = s.touched.size();
    for (size_t a = 0; a < P; ++a) {
      const Eigen::Vector3d p = point_position(data, s.points[a]);
      const Eigen::Vector3d v = point_velocity(data, s.points[a]);
      for (int c = 0; c < 3; ++c) {
        s.p[3 * a + static_cast<size_t>(c)] = p[c];
        s.v[3 * a + static_cast<size_t>(c)] = v[c];
      }
    }
    if (s.api.ops.coupling_jacobian != nullptr) {
      std::fill(s.dR_dp.begin(), s.dR_dp.end(), 0.0);
      std::fill(s.dR_dv.begin(), s.dR_dv.end(), 0.0);
      std::fill(s.dF_dy.begin(), s.dF_dy.end(), 0.0);
      std::fill(s.dF_dydot.begin(), s.dF_dydot.end(), 0.0);
      point_at(ev, s);
      refresh_signals(s, ev);
      st = normalized(in_flight(*s.host, InstanceHost::Op::coupling_jacobian, [&] {
        return s.api.ops.coupling_jacobian(s.api.self, &ev, s.dR_dp.data(), s.dR_dv.data(),
                                           s.dF_dy.data(), s.dF_dydot.data());
      }));
      check_guards(*s.host, "coupling_jacobian",
                   {{&s.dR_dp, "dR_dp"},
                    {&s.dR_dv, "dR_dv"},
                    {&s.dF_dy, "dF_dy"},
                    {&s.dF_dydot, "dF_dydot"}});
      if (status_ok(st)) apply_planted(planted, s, 2, {&s.dR_dp, &s.dR_dv, &s.dF_dy, &s.dF_dydot});
      // Along the integrator's map (Eq. 33): d/dy + dydot_dy d/dydot.
      for (size_t b = 0; b < k; ++b) {
        const double cv = states.algebraic[static_cast<size_t>(s.touched[b])] != 0 ? 0.0 : dydot_dy;
        for (size_t i = 0; i < n3; ++i) s.dF_dy[b * n3 + i] += cv * s.dF_dydot[b * n3 + i];
      }
    } else {
      st = difference_instance(s, ev, states.y, states.ydot, states.algebraic, dydot_dy,
                               work.derivs.rows_discard);
    }
    if (!status_ok(st)) {
      registry.outputs = work.derivs.saved_outputs;
      return st;
    }
    for (size_t a = 0; a < P; ++a) {
      const BodyPoint& pt = s.points[a];
      if (pt.body == kGround) continue;  // a fixed point: no motion, its force goes to the ground
      const Eigen::Vector3d p(s.p[3 * a], s.p[3 * a + 1], s.p[3 * a + 2]);
      point_jacobian(model, data, pt, work.coupling.point_jp);
      point_velocity_jacobian(model, data, pt, p, work.coupling.point_jv);
      work.coupling.point_dp_dx.noalias() = work.coupling.point_jp * work.coupling.map_dz_dx;
      work.coupling.point_dv_dx.noalias() = work.coupling.point_jv * work.coupling.map_dz_dx;
      work.coupling.point_dv_dx.noalias() += work.coupling.point_jp * work.coupling.map_dzd_total;
      // The instance's rows in the mechanical columns.
      for (size_t row = 0; row < k; ++row) {
        const int* slots = s.rows_in_mech.data() + row * static_cast<size_t>(n_m);
        for (int c = 0; c < n_m; ++c) {
          if (work.tangent_ws.mech_column_given[static_cast<size_t>(c)] == 0)
            continue;  // differenced
          const int slot = slots[c];
          if (slot < 0) continue;  // c moves none of its points
          double d = 0.0;
          for (int i = 0; i < 3; ++i)
            d += s.dR_dp[(3 * a + static_cast<size_t>(i)) * k + row] *
                     work.coupling.point_dp_dx(i, c) +
                 s.dR_dv[(3 * a + static_cast<size_t>(i)) * k + row] *
                     work.coupling.point_dv_dx(i, c);
          work.tangent_ws.values[static_cast<size_t>(slot)] += d;
        }
      }
      // The mechanical rows in the instance's state columns: dr/dQ' J_p^T,
      // formed once per point, times each state's dF.
      work.coupling.dr_dF.noalias() = work.coupling.map_dr_dQ * work.coupling.point_jp.transpose();
      for (size_t b = 0; b < k; ++b) {
        const Eigen::Vector3d dF(s.dF_dy[b * n3 + 3 * a], s.dF_dy[b * n3 + 3 * a + 1],
                                 s.dF_dy[b * n3 + 3 * a + 2]);
        const int* slots = s.mech_in_cols.data() + b * static_cast<size_t>(n_m);
        for (int rr = 0; rr < n_m; ++rr)
          if (slots[rr] >= 0)
            work.tangent_ws.values[static_cast<size_t>(slots[rr])] +=
                work.coupling.dr_dF.row(rr).dot(dF);
      }
    }
  }
  registry.outputs = work.derivs.saved_outputs;
  return MH_OK;
}

}  // namespace mh
