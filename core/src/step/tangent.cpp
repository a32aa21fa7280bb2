// The shared Newton tangent d r / d x (Eq. 37) over x = [formulation
// unknowns; subsystem states], with the rates tied to x by the integrator's
// map: dr/dx + dxd_dx dr/dxd + dxdd_dx dr/dxdd. Its sparsity pattern is
// analysed once from what the instances declared at setup; its values come
// from the plugins' analytic blocks where they give them and from forward
// differences (Eqs. 40-41) where they do not.
#include <algorithm>
#include <cmath>
#include <utility>

#include "engine.hpp"
#include "monohydra/core/mechanical_coupling.hpp"
#include "monohydra/core/plugin_registry.hpp"

namespace mh {

void Simulation::Engine::build_pattern() {
  n = n_m + n_s;
  // Unknowns that are the joint coordinates (the formulation says so with
  // MH_EXT_COORDINATE_UNKNOWNS) couple as the topology does
  // (mechanical_coupling.cpp): a tree of bounded depth gets a tangent of O(N)
  // entries. Other unknowns couple densely (e.g. independent coordinates,
  // whose dependent ones may move the whole mechanism).
  const bool topological =
      formulation.ops.get_extension != nullptr &&
      formulation.ops.get_extension(formulation.self, MH_EXT_COORDINATE_UNKNOWNS) != nullptr;
  if (topological && n_m != N)
    throw PluginError("formulation '" + formulation_name + "' declares " +
                      MH_EXT_COORDINATE_UNKNOWNS + " (its unknowns are the " + std::to_string(N) +
                      " joint coordinates) but added " + std::to_string(n_m) + " unknowns");
  // The formulation's blocks are then cleared and read on the pattern only
  // (assemble_tangent, check_formulation_blocks): O(nonzeros), not 3 n_m^2.
  work.tangent_ws.coordinate_unknowns = topological;
  // The mechanical unknowns each subsystem with points moves and is moved by.
  std::vector<std::vector<int>> moved(subsystems.size());
  std::vector<int> all_mechanical(static_cast<size_t>(n_m));
  for (int k = 0; k < n_m; ++k) all_mechanical[static_cast<size_t>(k)] = k;
  for (size_t i = 0; i < subsystems.size(); ++i) {
    const auto& s = subsystems[i];
    if (s.points.empty()) continue;
    if (!topological) {
      moved[i] = all_mechanical;
      continue;
    }
    std::vector<int> bodies;
    for (const BodyPoint& p : s.points) bodies.push_back(p.body);
    moved[i] = coordinates_moving(model, bodies);
  }
  std::vector<std::pair<int, int>> entries;
  if (topological) {
    entries = mechanical_coupling(model, moved);
  } else {
    for (int c = 0; c < n_m; ++c)
      for (int rr = 0; rr < n_m; ++rr) entries.emplace_back(rr, c);
  }
  for (size_t i = 0; i < subsystems.size(); ++i) {
    const auto& s = subsystems[i];
    if (s.declared.empty()) {  // its block is dense
      for (int a : s.touched)
        for (int b : s.touched) entries.emplace_back(n_m + a, n_m + b);
    } else {  // the entries it declared (sparsity.h) and the diagonal
      for (int a : s.touched) entries.emplace_back(n_m + a, n_m + a);
      for (const auto& [row, col] : s.declared) entries.emplace_back(n_m + row, n_m + col);
    }
    // Its rows see the kinematics; its forces enter the mechanical rows.
    for (int a : s.touched)
      for (int k : moved[i]) {
        entries.emplace_back(n_m + a, k);
        entries.emplace_back(k, n_m + a);
      }
  }
  work.tangent_ws.pattern = std::make_shared<const SparsePattern>(n, std::move(entries));
  work.tangent_ws.any_points = false;
  for (const auto& s : subsystems)
    work.tangent_ws.any_points = work.tangent_ws.any_points || !s.points.empty();
  work.tangent_ws.values.assign(static_cast<size_t>(work.tangent_ws.pattern->nonzeros()), 0.0);
  work.tangent_ws.groups = work.tangent_ws.pattern->column_groups();
  work.tangent_ws.mech_column_start.assign(1, 0);
  work.tangent_ws.mech_row_index.clear();
  if (topological) {
    const auto& colptr = work.tangent_ws.pattern->column_start();
    const auto& rows = work.tangent_ws.pattern->row_index();
    for (int c = 0; c < n_m; ++c) {  // a column's mechanical rows come first
      for (int k = colptr[c]; k < colptr[c + 1] && rows[k] < n_m; ++k)
        work.tangent_ws.mech_row_index.push_back(rows[k]);
      work.tangent_ws.mech_column_start.push_back(
          static_cast<int32_t>(work.tangent_ws.mech_row_index.size()));
    }
  }

  // Which state columns are fully covered by analytic blocks.
  work.tangent_ws.column_analytic.assign(static_cast<size_t>(n_s), 1);
  std::vector<char> state_feeds_mech(static_cast<size_t>(n_s), 0);
  for (const auto& s : subsystems)
    for (int a : s.touched) {
      if (s.api.ops.jacobian == nullptr)
        work.tangent_ws.column_analytic[static_cast<size_t>(a)] = 0;
      if (!s.points.empty()) state_feeds_mech[static_cast<size_t>(a)] = 1;
    }
  // State columns that need differences; the mechanical ones are decided per
  // assembly (the formulation says which columns it gave).
  work.tangent_ws.group_needs_fd.assign(work.tangent_ws.groups.size(), 0);
  for (size_t g = 0; g < work.tangent_ws.groups.size(); ++g) {
    for (int c : work.tangent_ws.groups[g]) {
      if (c < n_m) continue;
      if (work.tangent_ws.column_analytic[static_cast<size_t>(c - n_m)] == 0 ||
          state_feeds_mech[static_cast<size_t>(c - n_m)] != 0)
        work.tangent_ws.group_needs_fd[g] = 1;
    }
  }
  for (Eigen::MatrixXd* b :
       {&work.tangent_ws.dr_dx, &work.tangent_ws.dr_dxd, &work.tangent_ws.dr_dxdd})
    b->setZero(n_m, n_m);
  work.tangent_ws.mech_column_given.assign(static_cast<size_t>(n_m), 0);
  for (auto& s : subsystems) {
    const size_t k = s.touched.size();
    s.slots.resize(k * k);
    s.d_dy.resize(k * k);
    s.d_dydot.resize(k * k);
    for (size_t a = 0; a < k; ++a)
      for (size_t b = 0; b < k; ++b)
        s.slots[b * k + a] = work.tangent_ws.pattern->slot(n_m + s.touched[a], n_m + s.touched[b]);
    if (s.declared.empty()) continue;
    // A declared block: its entries outside the declaration are zero, and
    // another instance's entry in the same place is not its to write.
    std::vector<char> own(k * k, 0);
    auto local = [&](int state) {
      return static_cast<size_t>(std::find(s.touched.begin(), s.touched.end(), state) -
                                 s.touched.begin());
    };
    for (size_t a = 0; a < k; ++a) own[a * k + a] = 1;
    for (const auto& [row, col] : s.declared) own[local(col) * k + local(row)] = 1;
    for (size_t e = 0; e < k * k; ++e)
      if (own[e] == 0) s.slots[e] = -1;
  }
  for (auto& s : subsystems) {
    const size_t k = s.touched.size();
    s.block.clear();
    s.block_columns.clear();
    for (size_t b = 0; b < k; ++b) {
      const size_t begin = s.block.size();
      for (size_t a = 0; a < k; ++a)
        if (s.slots[b * k + a] >= 0)
          s.block.push_back({static_cast<int>(b * k + a), s.slots[b * k + a]});
      if (s.block.size() > begin) s.block_columns.push_back({s.touched[b], begin, s.block.size()});
    }
    s.undeclared.resize(0);
    s.block_checked = false;
    if (s.declared.empty()) continue;
    s.undeclared.setZero(static_cast<Eigen::Index>(k * k));
    for (size_t e = 0; e < k * k; ++e)
      if (s.slots[e] < 0) s.undeclared[static_cast<Eigen::Index>(e)] = 1.0;
  }
  work.solver.linear_solver = make_linear_solver(*work.tangent_ws.pattern, settings.linear);
  for (Eigen::VectorXd* v :
       {&run.x, &run.xd, &run.xdd, &work.r, &work.tangent_ws.r_pert, &work.solver.dx,
        &work.solver.dx_trial, &work.solver.dx_correction, &work.tangent_ws.eps,
        &work.map_ws.x_pred, &work.map_ws.xd_off, &work.map_ws.xdd_off})
    v->setZero(n);
}

mh_status Simulation::Engine::residual(double t_eval, const Eigen::VectorXd& xq,
                                       Eigen::VectorXd& rq) {
  rates_of(xq, run.xd, run.xdd);
  return residual_at(t_eval, xq, run.xd, run.xdd, rq);
}

mh_status Simulation::Engine::residual_at(double t_eval, const Eigen::VectorXd& xq,
                                          const Eigen::VectorXd& xdq, const Eigen::VectorXd& xddq,
                                          Eigen::VectorXd& rq) {
  states.y = xq.tail(n_s);
  states.ydot = xdq.tail(n_s);
  ++run.counters.residual_evaluations;
  work.eval.rows_target = rq.data() + n_m;
  work.eval.iterate_evaluated = false;
  const mh_status st = normalized(in_flight(*formulation_host, InstanceHost::Op::residual, [&] {
    const mh_unknown_values at = monohydra::unknown_values(t_eval, static_cast<size_t>(n_m),
                                                           xq.data(), xdq.data(), xddq.data());
    return formulation.ops.residual(formulation.self, &at, rq.data());
  }));
  work.eval.rows_target = nullptr;
  if (status_ok(st) && !work.eval.iterate_evaluated) {
    reports.last_plugin_error = "formulation '" + formulation_name +
                                "' broke the ABI contract: its residual did not call "
                                "evaluate_mechanics with MH_EVAL_SUBSYSTEMS";
    return MH_ERROR;
  }
  return st;
}

// One pass over the assembled values (v * 0 is 0 only for a finite v); on a
// non-finite one, the plugins' buffers read into them are searched for the
// writer, in the order they were read.
void Simulation::Engine::check_tangent_values() const {
  if (all_finite(work.tangent_ws.values.data(), work.tangent_ws.values.size())) return;
  if (formulation.ops.tangent != nullptr) check_formulation_blocks();
  if (work.tangent_ws.any_points && work.coupling.coupling_possible) {
    const std::pair<const Eigen::MatrixXd*, const char*> maps[] = {
        {&work.coupling.map_dz_dx, "dz_dx"},
        {&work.coupling.map_dzd_dx, "dzd_dx"},
        {&work.coupling.map_dzd_dxd, "dzd_dxd"},
        {&work.coupling.map_dr_dQ, "dr_dQ"}};
    for (const auto& [block, name] : maps)
      check_finite(block->data(), static_cast<size_t>(block->size()), *formulation_host,
                   "mechanics_map", name);
  }
  for (const SubsystemInstance& s : subsystems) {
    if (s.api.ops.jacobian != nullptr) {
      check_finite(s.d_dy.data(), s.d_dy.size(), *s.host, "jacobian", "d_dy");
      check_finite(s.d_dydot.data(), s.d_dydot.size(), *s.host, "jacobian", "d_dydot");
    }
    if (s.api.ops.coupling_jacobian != nullptr && work.coupling.coupling_possible) {
      check_finite(s.dR_dp.data(), s.dR_dp.size(), *s.host, "coupling_jacobian", "dR_dp");
      check_finite(s.dR_dv.data(), s.dR_dv.size(), *s.host, "coupling_jacobian", "dR_dv");
      check_finite(s.dF_dy.data(), s.dF_dy.size(), *s.host, "coupling_jacobian", "dF_dy");
      check_finite(s.dF_dydot.data(), s.dF_dydot.size(), *s.host, "coupling_jacobian", "dF_dydot");
    }
  }
  // No plugin buffer holds it: a difference of finite residuals overflowed.
  const auto& colptr = work.tangent_ws.pattern->column_start();
  for (int c = 0; c < n; ++c)
    for (int k = colptr[c]; k < colptr[c + 1]; ++k)
      if (!std::isfinite(work.tangent_ws.values[static_cast<size_t>(k)]))
        fail_step("the tangent's column of " + unknown_name(c) +
                  " is not finite: its forward differences of the residual overflowed");
}

// Outside the topological pattern of coordinate unknowns the blocks are not
// read (and not zeroed): only the entries read are checked, O(nonzeros).
void Simulation::Engine::check_formulation_blocks() const {
  const Eigen::MatrixXd* blocks[3] = {&work.tangent_ws.dr_dx, &work.tangent_ws.dr_dxd,
                                      &work.tangent_ws.dr_dxdd};
  const char* names[3] = {"dr_dx (column-major)", "dr_dxd (column-major)",
                          "dr_dxdd (column-major)"};
  for (int b = 0; b < 3; ++b) {
    const double* v = blocks[b]->data();
    if (!work.tangent_ws.coordinate_unknowns) {
      check_finite(v, static_cast<size_t>(blocks[b]->size()), *formulation_host, "tangent",
                   names[b]);
      continue;
    }
    const auto& colptr = work.tangent_ws.pattern->column_start();
    const auto& rows = work.tangent_ws.pattern->row_index();
    for (int c = 0; c < n_m; ++c)
      for (int k = colptr[c]; k < colptr[c + 1] && rows[k] < n_m; ++k) {
        const auto at = static_cast<size_t>(c) * static_cast<size_t>(n_m) + rows[k];
        if (!std::isfinite(v[at]))
          fail_nonfinite(v[at], at, *formulation_host, "tangent", names[b], true);
      }
  }
}

mh_status Simulation::Engine::assemble_tangent(double t_eval) {
  std::fill(work.tangent_ws.values.begin(), work.tangent_ws.values.end(), 0.0);
  // Analytic blocks first: they are defined at the x of the last residual
  // call, which the forward differences below move away from.
  std::fill(work.tangent_ws.mech_column_given.begin(), work.tangent_ws.mech_column_given.end(), 0);
  if (formulation.ops.tangent != nullptr) {
    if (work.tangent_ws.coordinate_unknowns) {
      // Zero on entry where the host reads them; outside the topological
      // pattern the blocks are structurally zero and ignored (O(nonzeros),
      // not O(n_m^2)).
      const auto& colptr = work.tangent_ws.pattern->column_start();
      const auto& rows = work.tangent_ws.pattern->row_index();
      for (int c = 0; c < n_m; ++c)
        for (int k = colptr[c]; k < colptr[c + 1] && rows[k] < n_m; ++k) {
          work.tangent_ws.dr_dx(rows[k], c) = 0.0;
          work.tangent_ws.dr_dxd(rows[k], c) = 0.0;
          work.tangent_ws.dr_dxdd(rows[k], c) = 0.0;
        }
    } else {
      for (Eigen::MatrixXd* b :
           {&work.tangent_ws.dr_dx, &work.tangent_ws.dr_dxd, &work.tangent_ws.dr_dxdd})
        b->setZero();
    }
    const mh_status st = normalized(in_flight(*formulation_host, InstanceHost::Op::tangent, [&] {
      const mh_unknown_values at = monohydra::unknown_values(
          t_eval, static_cast<size_t>(n_m), run.x.data(), run.xd.data(), run.xdd.data());
      const mh_tangent_blocks blocks{
          sizeof(mh_tangent_blocks),      static_cast<uint32_t>(n_m),
          work.tangent_ws.dr_dx.data(),   work.tangent_ws.dr_dxd.data(),
          work.tangent_ws.dr_dxdd.data(), work.tangent_ws.mech_column_given.data()};
      return formulation.ops.tangent(formulation.self, &at, &blocks);
    }));
    if (!status_ok(st)) return st;
    Eigen::MatrixXd* const written[3] = {&work.tangent_ws.dr_dx, &work.tangent_ws.dr_dxd,
                                         &work.tangent_ws.dr_dxdd};
    apply_planted(planted, written);
  }
  // With the formulation's mechanics map the subsystems with points
  // couple analytically (subsystem_coupling.cpp): no residual is differenced
  // in a state column that feeds the mechanics, nor in a mechanical column the
  // formulation's tangent gave. Read here, at the iterate, before the
  // differences below move x.
  const bool coupled = work.tangent_ws.any_points && work.coupling.coupling_possible;
  if (coupled) {
    const mh_status st = read_mechanics_map();
    if (!status_ok(st)) return st;
  }
  mh_subsystem_eval ev = subsystem_eval(t_eval, work.eval.scratch_rows.data());
  for (auto& s : subsystems) {
    if (s.api.ops.jacobian == nullptr) continue;
    if (s.undeclared.size() != 0 && s.block_checked) {
      // A declared block, checked: only its entries were written; clearing
      // them alone keeps the assembly linear in the block's entries.
      for (const auto& be : s.block) {
        s.d_dy[static_cast<size_t>(be.local)] = 0.0;
        s.d_dydot[static_cast<size_t>(be.local)] = 0.0;
      }
    } else {
      std::fill(s.d_dy.begin(), s.d_dy.end(), 0.0);
      std::fill(s.d_dydot.begin(), s.d_dydot.end(), 0.0);
    }
    point_at(ev, s);
    refresh_signals(s, ev);
    const mh_status st = normalized(in_flight(*s.host, InstanceHost::Op::jacobian, [&] {
      return s.api.ops.jacobian(s.api.self, &ev, s.d_dy.data(), s.d_dydot.data());
    }));
    check_guards(*s.host, "jacobian", {{&s.d_dy, "d_dy"}, {&s.d_dydot, "d_dydot"}});
    if (!status_ok(st)) return st;
    apply_planted(planted, s, 0, {&s.d_dy, &s.d_dydot});
    // A declared block (sparsity.h) holds every entry the instance writes:
    // checked at its first jacobian in one vectorized pass, and the entry
    // searched for only when it fails.
    if (s.undeclared.size() == 0 || s.block_checked) continue;
    s.block_checked = true;
    const auto n_block = s.undeclared.size();
    const Eigen::Map<const Eigen::ArrayXd> dy(s.d_dy.data(), n_block);
    const Eigen::Map<const Eigen::ArrayXd> dydot(s.d_dydot.data(), n_block);
    if (((dy.abs() + dydot.abs()) * s.undeclared).sum() == 0.0) continue;
    const size_t k = s.touched.size();
    for (size_t e = 0; e < k * k; ++e)
      if (s.slots[e] < 0 && (s.d_dy[e] != 0.0 || s.d_dydot[e] != 0.0))
        fail((s.host->label.empty() ? s.host->source : s.host->label) +
             " wrote a non-zero entry in jacobian outside the entries it declared "
             "(declare_entries): row " +
             states.state_info[static_cast<size_t>(s.touched[e % k])].qualified + ", column " +
             states.state_info[static_cast<size_t>(s.touched[e / k])].qualified);
  }

  // Forward differences by column groups, Eqs. (40)-(41).
  const auto& colptr = work.tangent_ws.pattern->column_start();
  const auto& rows = work.tangent_ws.pattern->row_index();
  for (size_t g = 0; g < work.tangent_ws.groups.size(); ++g) {
    bool needs = false;
    for (int c : work.tangent_ws.groups[g]) {
      if (c < n_m)
        needs = needs || work.tangent_ws.mech_column_given[static_cast<size_t>(c)] == 0 ||
                (work.tangent_ws.any_points && !coupled);
      else if (coupled)
        needs = needs || work.tangent_ws.column_analytic[static_cast<size_t>(c - n_m)] == 0;
      else
        needs = needs || work.tangent_ws.group_needs_fd[g] != 0;
    }
    if (!needs) continue;
    for (int c : work.tangent_ws.groups[g]) {
      work.tangent_ws.eps[c] = 1e-8 * std::max(1e-2, std::abs(run.x[c]));  // Eq. (41)
      run.x[c] += work.tangent_ws.eps[c];
    }
    const mh_status st = residual(t_eval, run.x, work.tangent_ws.r_pert);
    for (int c : work.tangent_ws.groups[g]) run.x[c] -= work.tangent_ws.eps[c];
    if (!status_ok(st)) return st;
    for (int c : work.tangent_ws.groups[g])
      for (int k = colptr[c]; k < colptr[c + 1]; ++k)
        work.tangent_ws.values[static_cast<size_t>(k)] =
            (work.tangent_ws.r_pert[rows[k]] - work.r[rows[k]]) / work.tangent_ws.eps[c];
  }
  // Restore the state the step's base evaluation left (rates, y, ydot at x).
  rates_of(run.x, run.xd, run.xdd);
  states.y = run.x.tail(n_s);
  states.ydot = run.xd.tail(n_s);

  // The formulation's columns: dr/dx + dxd_dx dr/dxd + dxdd_dx dr/dxdd.
  const mh_step_coefficients& cf = work.map_ws.map.coefficients;
  if (!work.tangent_ws.any_points || coupled) {
    for (int c = 0; c < n_m; ++c) {
      if (work.tangent_ws.mech_column_given[static_cast<size_t>(c)] == 0) continue;
      const uint8_t kind = registry.kinds[static_cast<size_t>(c)];
      const double cv = kind == MH_UNKNOWN_SECOND_ORDER  ? cf.dxd_dx_second
                        : kind == MH_UNKNOWN_FIRST_ORDER ? cf.dxd_dx_first
                                                         : 0.0;
      const double ca = kind == MH_UNKNOWN_SECOND_ORDER ? cf.dxdd_dx_second : 0.0;
      // The column's mechanical rows come first (sorted); entries outside the
      // pattern are structurally zero (MH_EXT_COORDINATE_UNKNOWNS).
      for (int k = colptr[c]; k < colptr[c + 1] && rows[k] < n_m; ++k) {
        const int rr = rows[k];
        work.tangent_ws.values[static_cast<size_t>(k)] = work.tangent_ws.dr_dx(rr, c) +
                                                         cv * work.tangent_ws.dr_dxd(rr, c) +
                                                         ca * work.tangent_ws.dr_dxdd(rr, c);
      }
    }
  }
  if (coupled) {
    const mh_status st = couple_subsystems(t_eval);
    if (!status_ok(st)) return st;
  }
  // d r / d y_{k+1} = d r / d y + dydot_dy d r / d ydot, Eq. (33); summed over
  // the instances that share a state, in the columns where all of them are analytic.
  const double dydot_dy = cf.dxd_dx_first;
  for (const auto& s : subsystems)
    for (const auto& col : s.block_columns) {
      if (work.tangent_ws.column_analytic[static_cast<size_t>(col.state)] == 0) continue;
      for (size_t i = col.begin; i < col.end; ++i)
        work.tangent_ws.values[static_cast<size_t>(s.block[i].slot)] = 0.0;
    }
  for (const auto& s : subsystems)
    for (const auto& col : s.block_columns) {
      const auto state = static_cast<size_t>(col.state);
      if (work.tangent_ws.column_analytic[state] == 0) continue;
      // An algebraic state has no rate: its column is d r / d y alone.
      const double cv = states.algebraic[state] != 0 ? 0.0 : dydot_dy;
      for (size_t i = col.begin; i < col.end; ++i) {
        const auto e = static_cast<size_t>(s.block[i].local);
        work.tangent_ws.values[static_cast<size_t>(s.block[i].slot)] +=
            s.d_dy[e] + cv * s.d_dydot[e];
      }
    }
  check_tangent_values();
  return MH_OK;
}

}  // namespace mh
