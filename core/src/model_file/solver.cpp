// solver: the time step, end time, Newton iteration limit, position
// tolerance and how often a failed step may be halved.
#include "parser.hpp"

namespace mh::model_file_detail {

SolverSettings Parser::solver(const YAML::Node& node) const {
  const MapView map(*this, node, "solver",
                    {"dt", "t_end", "max_iterations", "tol_position", "max_step_halvings"});
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
  return settings;
}

}  // namespace mh::model_file_detail
