// A subsystem instance's derivative arrays against differences of its own
// evaluate (Simulation::subsystem_blocks), and the test hook that plants an
// error in one of them. Why apart from the assembled tangent: there each
// entry is a sum (dR/dy + (2/h) dR/dydot, and every instance sharing a
// node), in which a 1 % error of one term can hide below another; block by
// block each entry is compared in its own pair of units.
#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/column_differences.hpp"
#include "engine.hpp"
#include "monohydra/core/dynamics.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {
namespace {

SubsystemInstance& instance_named(Simulation::Engine& e, const std::string& name) {
  for (SubsystemInstance& s : e.subsystems)
    if (s.spec != nullptr && s.spec->name == name) return s;
  std::string known;
  for (const SubsystemInstance& s : e.subsystems)
    if (s.spec != nullptr) known += (known.empty() ? "" : ", ") + s.spec->name;
  throw std::invalid_argument("no subsystem instance '" + name +
                              "' (the model's: " + (known.empty() ? "none" : known) + ")");
}

// A point by its key in the model file (points/<key>), else its number.
std::string point_name(const SubsystemInstance& s, size_t a) {
  const BodyPoint& pt = s.points[a];
  for (const auto& [key, spec] : s.spec->points)
    if (spec.point.body == pt.body && spec.point.p_B == pt.p_B) return "point " + key;
  return "point " + std::to_string(a + 1);
}

}  // namespace

void Simulation::plant_derivative_error(const std::string& instance, const std::string& block,
                                        long entry, double factor) {
  Engine& e = *engine_;
  // The formulation's tangent blocks, or an instance's derivative arrays.
  const bool formulation = instance.empty();
  const SubsystemInstance* s = formulation ? nullptr : &instance_named(e, instance);
  const char* const* names =
      formulation ? Simulation::FormulationBlocks::kNames : kDerivativeArrayNames;
  const int count = formulation ? 3 : 8;
  int array = -1;
  std::string known;
  for (int a = 0; a < count; ++a) {
    if (block == names[a]) array = a;
    known += (a == 0 ? "" : ", ") + std::string(names[a]);
  }
  if (array < 0 || entry < 0)
    throw std::invalid_argument(
        "plant_derivative_error: '" + block + "' is not one of " +
        (formulation ? "the formulation's tangent blocks (" : "a subsystem's derivative blocks (") +
        known + "), or the entry is negative");
  e.planted = factor == 1.0
                  ? PlantedError{}
                  : PlantedError{s, formulation, array, static_cast<size_t>(entry), factor};
}

std::vector<Simulation::DerivativeBlock> Simulation::subsystem_blocks(const std::string& instance,
                                                                      bool differences) {
  Engine& e = *engine_;
  if (e.explicit_method)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "a subsystem's blocks need an implicit integrator's step; this run's "
                          "integrator is explicit");
  SubsystemInstance& s = instance_named(e, instance);
  const double t_next = e.run.accepted.t + e.settings.dt;
  e.prepare_step(t_next, e.settings.dt);
  const auto failed = [&](const std::string& what) {
    return SimulationError(
        e.run.accepted.t, e.run.accepted.step,
        "subsystem '" + instance + "' " + what + ": " + e.reports.last_plugin_error);
  };
  // The iterate's rows, then every instance's points where the iterate's
  // kinematics put them (the residual may have evaluated elsewhere last).
  if (!status_ok(e.residual(t_next, e.run.x, e.work.r))) throw failed("residual failed");
  e.kinematics_at(e.work.eval.z_iterate.data(), e.work.eval.zd_iterate.data());
  reset_applied_forces(e.model, e.data);
  if (!status_ok(e.evaluate_subsystems(t_next, e.work.eval.scratch_rows.data())))
    throw failed("evaluate failed");
  const Eigen::VectorXd saved_outputs = e.registry.outputs;

  const auto k = static_cast<Eigen::Index>(s.touched.size());
  const auto n3 = static_cast<Eigen::Index>(3 * s.points.size());
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(e.n_s);
  mh_subsystem_eval ev = e.subsystem_eval(t_next, rows.data());
  Engine::point_at(ev, s);

  // The analytic arrays, each op called once, the test hook after it.
  std::vector<double> arrays[8];
  const auto size = [](Eigen::Index r, Eigen::Index c) { return static_cast<size_t>(r * c); };
  arrays[0].assign(size(k, k), 0.0);
  arrays[1].assign(size(k, k), 0.0);
  arrays[2].assign(size(k, n3), 0.0);
  arrays[3].assign(size(k, n3), 0.0);
  arrays[4].assign(size(n3, k), 0.0);
  arrays[5].assign(size(n3, k), 0.0);
  arrays[6].assign(size(n3, n3), 0.0);
  arrays[7].assign(size(n3, n3), 0.0);
  bool given[8] = {};
  const auto call = [&](InstanceHost::Op op, auto&& f) {
    refresh_signals(s, ev);
    if (!status_ok(normalized(in_flight(*s.host, op, f)))) throw failed("derivative op failed");
  };
  if (s.api.ops.jacobian != nullptr) {
    call(InstanceHost::Op::jacobian,
         [&] { return s.api.ops.jacobian(s.api.self, &ev, arrays[0].data(), arrays[1].data()); });
    apply_planted(e.planted, s, 0, {&arrays[0], &arrays[1]});
    given[0] = given[1] = true;
  }
  if (n3 > 0 && s.api.ops.coupling_jacobian != nullptr) {
    call(InstanceHost::Op::coupling_jacobian, [&] {
      return s.api.ops.coupling_jacobian(s.api.self, &ev, arrays[2].data(), arrays[3].data(),
                                         arrays[4].data(), arrays[5].data());
    });
    apply_planted(e.planted, s, 2, {&arrays[2], &arrays[3], &arrays[4], &arrays[5]});
    given[2] = given[3] = given[4] = given[5] = true;
  }
  if (n3 > 0 && s.api.ops.point_force_jacobian != nullptr) {
    call(InstanceHost::Op::point_force_jacobian, [&] {
      return s.api.ops.point_force_jacobian(s.api.self, &ev, arrays[6].data(), arrays[7].data());
    });
    apply_planted(e.planted, s, 6, {&arrays[6], &arrays[7]});
    given[6] = given[7] = true;
  }

  // Names: rows R of the touched states, F of the points' force components.
  std::vector<std::string> state_names, rate_names, force_names, position_names, velocity_names;
  for (const int i : s.touched) {
    const std::string& q = e.states.state_info[static_cast<size_t>(i)].qualified;
    state_names.push_back(q);
    rate_names.push_back("rate of " + q);
  }
  for (size_t a = 0; a < s.points.size(); ++a)
    for (const char* axis : {" x", " y", " z"}) {
      const std::string p = point_name(s, a) + axis;
      force_names.push_back("force on " + p);
      position_names.push_back(p);
      velocity_names.push_back("velocity of " + p);
    }

  // The instance alone: its touched rows, then its point forces.
  const auto evaluate = [&]() -> Eigen::VectorXd {
    rows.setZero();
    std::fill(s.f.begin(), s.f.end(), 0.0);
    if (!status_ok(normalized(evaluate_instance(s, ev)))) throw failed("evaluate failed");
    Eigen::VectorXd g(k + n3);
    for (Eigen::Index a = 0; a < k; ++a) g[a] = rows[s.touched[static_cast<size_t>(a)]];
    for (Eigen::Index i = 0; i < n3; ++i) g[k + i] = s.f[static_cast<size_t>(i)];
    return g;
  };
  // One argument of four: its values gathered, and written back before
  // each evaluation.
  Eigen::VectorXd y(k), ydot(k), p(n3), v(n3);
  for (Eigen::Index a = 0; a < k; ++a) {
    y[a] = e.states.y[s.touched[static_cast<size_t>(a)]];
    ydot[a] = e.states.ydot[s.touched[static_cast<size_t>(a)]];
  }
  for (Eigen::Index i = 0; i < n3; ++i) {
    p[i] = s.p[static_cast<size_t>(i)];
    v[i] = s.v[static_cast<size_t>(i)];
  }
  const auto put = [&] {
    for (Eigen::Index a = 0; a < k; ++a) {
      e.states.y[s.touched[static_cast<size_t>(a)]] = y[a];
      e.states.ydot[s.touched[static_cast<size_t>(a)]] = ydot[a];
    }
    for (Eigen::Index i = 0; i < n3; ++i) {
      s.p[static_cast<size_t>(i)] = p[i];
      s.v[static_cast<size_t>(i)] = v[i];
    }
  };
  const Eigen::VectorXd g0 = evaluate();
  Simulation::TangentSample columns[4];  // of y, ydot, p, v: every row
  if (differences) {
    // A rate's step moves its state over one step of dt as the state's own
    // step does (a rate at rest would be stepped by 1e-8: below the
    // rounding of a row whose other terms are a flow's).
    const Eigen::VectorXd rate_scale = y.cwiseAbs() / e.settings.dt;
    Eigen::VectorXd* args[4] = {&y, &ydot, &p, &v};
    for (int a = 0; a < 4; ++a)
      difference_columns(
          *args[a], args[a]->size(), g0,
          [&]() {
            put();
            return evaluate();
          },
          columns[a], a == 1 ? &rate_scale : nullptr);
    put();
  }

  std::vector<DerivativeBlock> out;
  // Array a: rows R (top k) or F (bottom 3P) of column argument `arg`.
  const auto block = [&](int a, bool force_rows, int arg, const std::vector<std::string>& cols) {
    const Eigen::Index r0 = force_rows ? k : 0, m = force_rows ? n3 : k;
    const auto n = static_cast<Eigen::Index>(cols.size());
    if (m == 0 || n == 0) return;
    DerivativeBlock b;
    b.name = kDerivativeArrayNames[a];
    b.given = given[a];
    b.rows = force_rows ? force_names : state_names;
    b.columns = cols;
    b.sample.h = e.settings.dt;
    b.sample.analytic = Eigen::Map<const Eigen::MatrixXd>(arrays[a].data(), m, n);
    if (differences) {
      b.sample.forward = columns[arg].forward.middleRows(r0, m);
      b.sample.backward = columns[arg].backward.middleRows(r0, m);
      b.sample.central_coarse = columns[arg].central_coarse.middleRows(r0, m);
      b.sample.central_wide = columns[arg].central_wide.middleRows(r0, m);
      b.sample.central_wider = columns[arg].central_wider.middleRows(r0, m);
      b.sample.column_scale = columns[arg].column_scale;
    }
    out.push_back(std::move(b));
  };
  block(0, false, 0, state_names);
  block(1, false, 1, rate_names);
  block(2, false, 2, position_names);
  block(3, false, 3, velocity_names);
  block(4, true, 0, state_names);
  block(5, true, 1, rate_names);
  block(6, true, 2, position_names);
  block(7, true, 3, velocity_names);

  e.registry.outputs = saved_outputs;
  e.residual(t_next, e.run.x, e.work.r);  // the engine at the prediction again
  return out;
}

}  // namespace mh
