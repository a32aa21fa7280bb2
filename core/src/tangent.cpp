// The shared Newton tangent d r / d x (Eq. 37) over x = [mechanical unknowns;
// subsystem states]: its sparsity pattern, analysed once from what the
// instances declared at setup, and its values, from the plugins' analytic
// blocks where they give them and by forward differences (Eqs. 40-41) where
// they do not.
#include <algorithm>
#include <cmath>

#include "engine.hpp"

namespace mh {

void Simulation::Engine::build_pattern() {
  n = n_m + n_s;
  std::vector<std::pair<int, int>> entries;
  // Mechanical rows and columns: dense (the semirecursive M' couples them all).
  for (int c = 0; c < n_m; ++c)
    for (int rr = 0; rr < n_m; ++rr) entries.emplace_back(rr, c);
  for (const auto& s : subsystems) {
    for (int a : s.touched)
      for (int b : s.touched) entries.emplace_back(n_m + a, n_m + b);
    if (s.points.empty()) continue;
    // Its rows see the kinematics; its forces enter every mechanical row.
    for (int a : s.touched)
      for (int k = 0; k < n_m; ++k) {
        entries.emplace_back(n_m + a, k);
        entries.emplace_back(k, n_m + a);
      }
  }
  pattern = std::make_unique<SparsePattern>(n, std::move(entries));
  values.assign(static_cast<size_t>(pattern->nonzeros()), 0.0);
  groups = pattern->column_groups();

  // Which columns are fully covered by analytic blocks.
  const bool mech_analytic = formulation->tangent != nullptr;
  bool any_points = false;
  for (const auto& s : subsystems) any_points = any_points || !s.points.empty();
  column_analytic.assign(static_cast<size_t>(n_s), 1);
  std::vector<char> state_feeds_mech(static_cast<size_t>(n_s), 0);
  for (const auto& s : subsystems)
    for (int a : s.touched) {
      if (s.api->jacobian == nullptr) column_analytic[static_cast<size_t>(a)] = 0;
      if (!s.points.empty()) state_feeds_mech[static_cast<size_t>(a)] = 1;
    }
  group_needs_fd.assign(groups.size(), 0);
  for (size_t g = 0; g < groups.size(); ++g) {
    for (int c : groups[g]) {
      const bool needs = c < n_m ? (!mech_analytic || any_points)
                                 : (column_analytic[static_cast<size_t>(c - n_m)] == 0 ||
                                    state_feeds_mech[static_cast<size_t>(c - n_m)] != 0);
      if (needs) group_needs_fd[g] = 1;
    }
  }
  mech_slots.resize(static_cast<size_t>(n_m) * static_cast<size_t>(n_m));
  for (int c = 0; c < n_m; ++c)
    for (int rr = 0; rr < n_m; ++rr)
      mech_slots[static_cast<size_t>(c) * static_cast<size_t>(n_m) + static_cast<size_t>(rr)] =
          pattern->slot(rr, c);
  mech_tangent.resize(n_m, n_m);
  for (auto& s : subsystems) {
    const size_t k = s.touched.size();
    s.slots.resize(k * k);
    s.d_dy.resize(k * k);
    s.d_dydot.resize(k * k);
    for (size_t a = 0; a < k; ++a)
      for (size_t b = 0; b < k; ++b)
        s.slots[a * k + b] = pattern->slot(n_m + s.touched[a], n_m + s.touched[b]);
  }
  klu = std::make_unique<KluSolver>(*pattern);
  x.setZero(n);
  r.setZero(n);
  r_pert.setZero(n);
  dx.setZero(n);
  eps.setZero(n);
}

// r(x): the formulation's rows (which evaluate the subsystems' rows through
// the host) with ydot from the trapezoidal rule, Eq. (33).
mh_status Simulation::Engine::residual(double t_next, const Eigen::VectorXd& xq,
                                       Eigen::VectorXd& rq) {
  const double two_over_dt = 2.0 / settings.dt;
  y = xq.tail(n_s);
  ydot = two_over_dt * y + y_hat;  // Eq. (33)
  rows_target = rq.data() + n_m;
  iterate_evaluated = false;
  const mh_status st = formulation->residual(formulation, t_next, xq.data(), rq.data());
  if (st < MH_DISCARD && !iterate_evaluated) {
    last_plugin_error = "formulation '" + formulation_name +
                        "' broke the ABI contract: its residual did not call "
                        "evaluate_mechanics with MH_EVAL_SUBSYSTEMS";
    return MH_ERROR;
  }
  return st;
}

mh_status Simulation::Engine::assemble_tangent(double t_next) {
  std::fill(values.begin(), values.end(), 0.0);
  // Analytic blocks first: they are defined at the x of the last residual
  // call, which the forward differences below move away from.
  const bool mech_analytic = formulation->tangent != nullptr;
  if (mech_analytic) {
    const mh_status st = formulation->tangent(formulation, t_next, x.data(), mech_tangent.data());
    if (st >= MH_DISCARD) return st;
  }
  mh_subsystem_eval ev = subsystem_eval(t_next, scratch_rows.data());
  for (auto& s : subsystems) {
    if (s.api->jacobian == nullptr) continue;
    std::fill(s.d_dy.begin(), s.d_dy.end(), 0.0);
    std::fill(s.d_dydot.begin(), s.d_dydot.end(), 0.0);
    point_at(ev, s);
    const mh_status st = s.api->jacobian(s.api, &ev, s.d_dy.data(), s.d_dydot.data());
    if (st >= MH_DISCARD) return st;
  }

  // Forward differences by column groups, Eqs. (40)-(41).
  const auto& colptr = pattern->column_start();
  const auto& rows = pattern->row_index();
  for (size_t g = 0; g < groups.size(); ++g) {
    if (group_needs_fd[g] == 0) continue;
    for (int c : groups[g]) {
      eps[c] = 1e-8 * std::max(1e-2, std::abs(x[c]));  // Eq. (41)
      x[c] += eps[c];
    }
    const mh_status st = residual(t_next, x, r_pert);
    for (int c : groups[g]) x[c] -= eps[c];
    if (st >= MH_DISCARD) return st;
    for (int c : groups[g])
      for (int k = colptr[c]; k < colptr[c + 1]; ++k)
        values[static_cast<size_t>(k)] = (r_pert[rows[k]] - r[rows[k]]) / eps[c];
  }
  // Restore the state the step's base evaluation left (y, ydot at x).
  y = x.tail(n_s);
  ydot = (2.0 / settings.dt) * y + y_hat;

  if (mech_analytic)
    for (size_t k = 0; k < mech_slots.size(); ++k)
      values[static_cast<size_t>(mech_slots[k])] = mech_tangent.data()[k];
  // d r / d y_{k+1} = d r / d y + (2 / dt) d r / d ydot, Eq. (33); summed over the
  // instances that share a state, in the columns where all of them are analytic.
  const double two_over_dt = 2.0 / settings.dt;
  for (const auto& s : subsystems) {
    const size_t k = s.touched.size();
    for (size_t b = 0; b < k; ++b) {
      if (column_analytic[static_cast<size_t>(s.touched[b])] == 0) continue;
      for (size_t a = 0; a < k; ++a) values[static_cast<size_t>(s.slots[a * k + b])] = 0.0;
    }
  }
  for (const auto& s : subsystems) {
    const size_t k = s.touched.size();
    for (size_t b = 0; b < k; ++b) {
      if (column_analytic[static_cast<size_t>(s.touched[b])] == 0) continue;
      for (size_t a = 0; a < k; ++a)
        values[static_cast<size_t>(s.slots[a * k + b])] +=
            s.d_dy[a * k + b] + two_over_dt * s.d_dydot[a * k + b];
    }
  }
  return MH_OK;
}

}  // namespace mh
