// solver: the time step, end time, Newton iteration limit, position
// tolerance, how often a failed step may be halved, the linear solver and
// which Newton (full, per-step, modified, articulated or auto), and whether
// its increments are damped.
#include "parser.hpp"

namespace mh {
const char* to_string(NewtonKind kind) {
  switch (kind) {
    case NewtonKind::modified:
      return "modified";
    case NewtonKind::per_step:
      return "per-step";
    case NewtonKind::articulated:
      return "articulated";
    case NewtonKind::automatic:
      return "auto";
    case NewtonKind::full:
      break;
  }
  return "full";
}
}  // namespace mh

namespace mh::model_file_detail {

SolverSettings Parser::solver(const YAML::Node& node) const {
  const MapView map(*this, node, "solver",
                    {"dt", "t_end", "max_iterations", "tol_position", "max_step_halvings", "linear",
                     "newton", "line_search", "explicit_stability"});
  SolverSettings settings;
  settings.mark = mark(node);
  if (auto dt = map.get("dt")) {
    settings.dt = positive(*dt, "solver.dt");
    settings.dt_mark = mark(*dt);
  }
  if (auto t_end = map.get("t_end")) {
    settings.t_end = non_negative(*t_end, "solver.t_end");
    settings.t_end_mark = mark(*t_end);
  }
  if (auto iterations = map.get("max_iterations")) {
    settings.max_iterations = integer_at_least(*iterations, "solver.max_iterations", 1);
  }
  if (auto halvings = map.get("max_step_halvings")) {
    settings.max_step_halvings = integer_at_least(*halvings, "solver.max_step_halvings", 0);
    // The depth of the halving: one step may take up to 2^(depth+1) - 1
    // attempts, so 10 (2047 attempts, a few seconds at worst) bounds how long
    // a hopeless step is retried before the run stops.
    if (settings.max_step_halvings > 10)
      fail(*halvings, "solver.max_step_halvings", "expected an integer from 0 to 10");
  }
  if (auto tol = map.get("tol_position")) {
    settings.tol_position = positive(*tol, "solver.tol_position");
  }
  if (auto linear = map.get("linear")) {
    const std::string name = string(*linear, "solver.linear");
    bool known = false;
    for (LinearSolverKind kind : {LinearSolverKind::klu, LinearSolverKind::umfpack,
                                  LinearSolverKind::dense, LinearSolverKind::automatic}) {
      if (name != to_string(kind)) continue;
      settings.linear = kind;
      known = true;
    }
    if (!known)
      fail(*linear, "solver.linear",
           "expected one of: klu, umfpack, dense, auto (the tangent's linear solver; auto: dense "
           "LU for a dense tangent, KLU otherwise), got '" +
               name + "'");
  }
  const auto newton = map.get("newton");
  if (newton) {
    const std::string name = string(*newton, "solver.newton");
    bool known = false;
    for (NewtonKind kind : {NewtonKind::full, NewtonKind::per_step, NewtonKind::modified,
                            NewtonKind::articulated, NewtonKind::automatic}) {
      if (name != to_string(kind)) continue;
      settings.newton = kind;
      known = true;
    }
    if (!known)
      fail(*newton, "solver.newton",
           "expected auto, full, per-step, modified or articulated (a tangent at every iteration, "
           "once per step, kept across steps, or the mass matrix's articulated-body "
           "factorization in its place; auto: articulated for a deep tree, else per-step), got "
           "'" +
               name + "'");
  }
  if (auto search = map.get("line_search")) {
    const std::string name = string(*search, "solver.line_search");
    if (name != "on" && name != "off")
      fail(*search, "solver.line_search",
           "expected on or off (Newton's increments shortened until the iteration contracts), got "
           "'" +
               name + "'");
    settings.line_search = name == "on";
    // The damped step tests an increment with the factorization it came
    // from; a kept factorization's undo of a diverging increment needs the
    // residual of the iterate it returns to, which the test has overwritten.
    // So it damps full Newton, which it makes the default.
    if (settings.line_search && newton && settings.newton != NewtonKind::full &&
        settings.newton != NewtonKind::automatic)
      fail(*search, "solver.line_search",
           std::string("expected off with newton: ") + to_string(settings.newton) +
               " (the line search damps full Newton only)");
    if (settings.line_search) settings.newton = NewtonKind::full;
  }
  if (auto stability = map.get("explicit_stability")) {
    const std::string name = string(*stability, "solver.explicit_stability");
    if (!parse_explicit_stability(name, settings.explicit_stability))
      fail(*stability, "solver.explicit_stability",
           "expected error, warn or off (what an explicit integrator's step beyond its "
           "stability bound does to the run), got '" +
               name + "'");
  }
  return settings;
}

}  // namespace mh::model_file_detail
