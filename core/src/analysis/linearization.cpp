// The state-space matrices of a run about its accepted state
// (linearization.hpp), from the run's own converged implicit step.
//
// Why the step and not the residual's blocks: the step is what the run does,
// projections (penalty, Eqs. 20-21), dependent coordinates (double-step) and
// the analytic tangent Newton solves with included, so A is the dynamics the
// run shows (a closed loop's measured time constant is one of its
// eigenvalues) whichever formulation made it. The step's map is taken by
// central differences of whole steps from perturbed states:
//
// - each state starts consistent: with the perturbed positions, velocities
//   and subsystem states held, the accelerations, the states' rates and the
//   algebraic unknowns are solved from r(x, xd, xdd) = 0 (as an explicit
//   stage does, explicit_step.cpp) and the integrator restarts from there,
//   as after a time event. A history whose rates belong to another state
//   would make the trapezoidal rule's map a different one (for x' = a x the
//   column would be 1/(1 - ha/2) instead of (1 + ha/2)/(1 - ha/2));
// - the perturbation is the unknown's Newton tolerance (velocities: that
//   over h), and these steps' Newton runs to 1e-4 of its tolerances (the
//   run's own are put back after): what Newton leaves of a converged step
//   is then far below the perturbation, which stays small beside the
//   model's nonlinearities (a cylinder's friction, steepest at rest, is
//   smoothed over 0.01 m/s: on the four-bar ten times the tolerance over h,
//   1e-3 rad/s, moved the poles at rest by 1 %);
// - a formulation whose unknowns are the coordinates (penalty) is perturbed
//   within the constraints' tangent space (see below);
// - inputs are set as a program sets them (Simulation::set_input: a jump at
//   the accepted time), by a millionth of their range;
// - a step that would halve (solver.max_step_halvings) fails instead: a
//   halved step is another map.
//
// Every perturbed run is the saved state restored: the caller's run goes on
// from the same saved state, to the bit.
#include "monohydra/core/linearization.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine.hpp"
#include "monohydra/core/run_state.hpp"
#include "monohydra/core/tangent_reuse.hpp"
#include "monohydra/cpp/unknowns.hpp"
#include "state_slots.hpp"

namespace mh {

namespace {

// A state's perturbation in units of its unknown's Newton tolerance.
constexpr double kToleranceMultiple = 1.0;
constexpr double kTighten = 1e-4;
// An input's, relative to its range (or its value, or 1 when it has neither).
constexpr double kInputFraction = 1e-6;
enum class OutputKind { coordinate, coordinate_rate, state, output };
struct OutputRef {
  OutputKind kind = OutputKind::output;
  int index = 0;
  bool formulation = false;  // the formulation's: written at accept only
};

// What each asked-for output is, or std::invalid_argument naming it.
std::vector<OutputRef> resolve_outputs(const Simulation::Engine& e,
                                       const std::vector<std::string>& names,
                                       std::vector<LinearVariable>& described) {
  std::vector<OutputRef> refs;
  const auto& coords = e.registry.coordinate_names;
  for (const std::string& name : names) {
    OutputRef ref;
    LinearVariable var{name, ""};
    bool found = false;
    for (size_t j = 0; j < coords.size() && !found; ++j) {
      const std::string unit = e.registry.coordinate_is_angle[j] != 0 ? "rad" : "m";
      if (name == coords[j]) {
        ref = {OutputKind::coordinate, static_cast<int>(j), false};
        var.unit = unit;
        found = true;
      } else if (name == coords[j] + "_dot") {
        ref = {OutputKind::coordinate_rate, static_cast<int>(j), false};
        var.unit = unit + "/s";
        found = true;
      }
    }
    const auto find_in = [&](const std::vector<VariableInfo>& infos, OutputKind kind) {
      for (size_t j = 0; j < infos.size() && !found; ++j) {
        if (name.empty() || (infos[j].name != name && infos[j].qualified != name)) continue;
        const std::string owner = infos[j].qualified.substr(0, infos[j].qualified.find('.'));
        ref = {kind, static_cast<int>(j),
               kind == OutputKind::output && owner == e.formulation_name};
        var.unit = infos[j].unit;
        found = true;
      }
    };
    find_in(e.states.state_info, OutputKind::state);
    find_in(e.registry.output_info, OutputKind::output);
    if (!found) {
      std::string known;
      for (const std::string& c : coords)
        known += (known.empty() ? "" : ", ") + c + ", " + c + "_dot";
      for (const auto* infos : {&e.states.state_info, &e.registry.output_info})
        for (const VariableInfo& v : *infos)
          known += ", " + (v.name.empty() ? v.qualified : v.name);
      throw std::invalid_argument("linearize: unknown output '" + name +
                                  "' (expected a coordinate, its rate NAME_dot, a state or an "
                                  "output: " +
                                  known + ")");
    }
    refs.push_back(ref);
    described.push_back(var);
  }
  return refs;
}

// Restores the saved run (and the settings linearize changed) however it ends.
class RunRestorer {
 public:
  RunRestorer(Simulation& sim, Simulation::Engine& e, const RunState& saved)
      : sim_(sim),
        e_(e),
        saved_(saved),
        halvings_(e.settings.max_step_halvings),
        tol_(e.registry.tol) {}
  RunRestorer(const RunRestorer&) = delete;
  RunRestorer& operator=(const RunRestorer&) = delete;
  ~RunRestorer() {
    e_.settings.max_step_halvings = halvings_;
    e_.registry.tol = tol_;
    try {
      sim_.restore_state(saved_);
    } catch (...) {  // a state saved from this very run: not refused
    }
  }

 private:
  Simulation& sim_;
  Simulation::Engine& e_;
  const RunState& saved_;
  int halvings_;
  Eigen::VectorXd tol_;
};

}  // namespace

Linearization linearize(Simulation& sim, const std::vector<std::string>& output_names,
                        const LinearizeOptions& options) {
  Simulation::Engine& e = *sim.engine_;
  if (!e.run.accepted.started)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "linearize: the run has not started (call start() first)");
  if (e.explicit_method)
    throw SimulationError(e.run.accepted.t, e.run.accepted.step,
                          "linearize: the run's integrator '" + e.integrator_name +
                              "' is explicit; the linearisation differences an implicit step");
  Linearization out;
  const std::vector<OutputRef> refs = resolve_outputs(e, output_names, out.outputs);
  out.t = e.run.accepted.t;
  out.step = e.run.accepted.step;
  out.h = e.settings.dt;
  const double h = e.settings.dt;

  // X: positions and first-order unknowns of the formulation, the
  // velocities of its second-order ones, then the subsystems' states.
  const std::vector<StateSlot> slots = state_slots(e);
  out.states = state_variables(sim);
  static const std::vector<InputSpec> kNoInputs;
  const std::vector<InputSpec>& inputs = options.inputs ? sim.inputs() : kNoInputs;
  for (const InputSpec& in : inputs) out.inputs.push_back({in.name, in.unit});
  const auto n = static_cast<Eigen::Index>(slots.size());
  const auto m = static_cast<Eigen::Index>(inputs.size());
  const auto p = static_cast<Eigen::Index>(refs.size());

  std::vector<double> u_base;
  for (size_t k = 0; k < inputs.size(); ++k) u_base.push_back(sim.input(static_cast<int>(k)));
  const RunState saved = sim.save_state();
  const RunRestorer restorer(sim, e, saved);
  // A halved step would be another map: a perturbed step that fails is an error.
  e.settings.max_step_halvings = 0;
  const Eigen::VectorXd tol = e.registry.tol;
  ConsistentState consistent(e, "linearize");  // its scales: the run's own tolerances
  // The rates' Jacobian factored afresh at this state, for all of its
  // perturbed states (and kept for a correction after it): a map that does
  // not depend on which state the kept one was of.
  e.work.rate_factor.valid = false;

  // Y at the current (consistent) state, and X and the formulation's
  // outputs after the step from it.
  Eigen::VectorXd y_now(p), x_next(n), y_next(p);
  const auto read_now = [&] {
    for (Eigen::Index k = 0; k < p; ++k) {
      const OutputRef& r = refs[static_cast<size_t>(k)];
      switch (r.kind) {
        case OutputKind::coordinate:
          y_now[k] = e.run.accepted.z[r.index];
          break;
        case OutputKind::coordinate_rate:
          y_now[k] = e.run.accepted.zd[r.index];
          break;
        case OutputKind::state:
          y_now[k] = e.run.y[r.index];
          break;
        case OutputKind::output:
          y_now[k] = e.registry.outputs[r.index];  // of the state's evaluation
          break;
      }
    }
  };
  const auto read_next = [&] {
    for (Eigen::Index k = 0; k < n; ++k) x_next[k] = slot_value(e, slots[static_cast<size_t>(k)]);
    for (Eigen::Index k = 0; k < p; ++k) {
      const OutputRef& r = refs[static_cast<size_t>(k)];
      y_next[k] = r.kind == OutputKind::output ? e.run.outputs[r.index] : 0.0;
    }
  };
  // One side of a central difference: the perturbed state made consistent,
  // its outputs, one step.
  // Newton runs to kTighten of the tolerances; where round-off keeps an
  // increment above that (a controller's output whose gain multiplies the
  // sensor's round-off), the step is taken again at ten times it, up to the
  // run's own tolerances.
  //
  // Every side after the first keeps the tangent factored by the one
  // before (modified Newton: a state a Newton tolerance away has the same
  // tangent to far below its convergence rate's threshold), instead of
  // assembling and factoring its own: the same converged steps, for
  // residuals alone.
  TangentReuse kept;
  const auto side = [&](const auto& perturb, const char* what) {
    for (int level = 0;; ++level) {  // kTighten = 1e-4: levels 0 .. 4, the last the run's own
      e.registry.tol = tol * (kTighten * std::pow(10.0, level));
      sim.restore_state(saved);
      perturb();
      consistent.make(what);
      if (kept.keeps_factorization()) e.run.reuse = kept;
      read_now();
      try {
        e.step_once();
        break;
      } catch (const SimulationError& err) {
        kept.invalidate();
        if (level < 4) continue;
        throw SimulationError(
            err.time(), err.step(),
            std::string("linearize: the step from the state ") + what + " failed: " + err.reason());
      }
    }
    kept = e.run.reuse;
    kept.set_mode(TangentReuse::Mode::modified);
    read_next();
  };

  Eigen::MatrixXd phi(n, n), gamma(n, m), c(p, n), d(p, m), g_x(p, n), g_u(p, m);
  Eigen::VectorXd x_plus(n), y_now_plus(p), y_next_plus(p), widths(n);
  // Central: the sides at +1 and -1; one-sided (the states' columns, when
  // asked): at +1, beside the unperturbed step's (x_base, y_base), taken
  // once. An input's are central always (at a range's end one side is the
  // value itself).
  Eigen::VectorXd x_base(n), y_now_base(p), y_next_base(p);
  if (!options.central) {
    side([] {}, "unperturbed");
    x_base = x_next;
    y_now_base = y_now;
    y_next_base = y_next;
  }
  const auto difference = [&](const auto& perturb, double width, const char* what,
                              Eigen::MatrixXd& map, Eigen::MatrixXd& direct, Eigen::MatrixXd& after,
                              Eigen::Index col, bool central) {
    side([&] { perturb(+1.0); }, what);
    x_plus = x_next;
    y_now_plus = y_now;
    y_next_plus = y_next;
    if (central) side([&] { perturb(-1.0); }, what);
    const Eigen::VectorXd& x_minus = central ? x_next : x_base;
    const Eigen::VectorXd& y_now_minus = central ? y_now : y_now_base;
    const Eigen::VectorXd& y_next_minus = central ? y_next : y_next_base;
    const double w = central ? width : width / 2.0;
    map.col(col) = (x_plus - x_minus) / w;
    direct.col(col) = (y_now_plus - y_now_minus) / w;
    after.col(col) = (y_next_plus - y_next_minus) / w;
  };
  // A formulation whose unknowns are the coordinates (penalty) has more of
  // them than the mechanism's degrees of freedom: a coordinate moved alone
  // leaves the constraints (state_slots.hpp), and its step snaps back (its projections and
  // penalty forces) with a jump through every state a motion drives. Its
  // positions and velocities are moved within the constraints' tangent
  // space, P = I - Phi_z^+ Phi_z at the accepted z: the columns are then
  // Phi P, which has the eigenvalues of Phi on the constraints (the
  // mechanism's) and zeros across them (-2/h in A).
  const Eigen::MatrixXd tangent_space = constraint_tangent_space(e);
  for (Eigen::Index k = 0; k < n; ++k) {
    const StateSlot& s = slots[static_cast<size_t>(k)];
    const double step = kToleranceMultiple * tol[s.unknown] / (s.rate ? h : 1.0);
    widths[k] = step;
    const std::string what = "with " + out.states[static_cast<size_t>(k)].name + " perturbed";
    const bool within = tangent_space.size() > 0 && s.unknown < e.N;
    difference(
        [&](double sign) {
          if (!within) {
            slot_value(e, s) += sign * step;
            return;
          }
          Eigen::VectorXd& v = s.rate ? e.run.xd : e.run.x;
          v.head(e.N) += (sign * step) * tangent_space.col(s.unknown);
        },
        2.0 * step, what.c_str(), phi, c, g_x, k, options.central);
  }
  for (Eigen::Index k = 0; k < m; ++k) {
    const InputSpec& spec = inputs[static_cast<size_t>(k)];
    const int input = static_cast<int>(k);
    const double u = u_base[static_cast<size_t>(k)];
    const double span = spec.min < spec.max ? spec.max - spec.min : 0.0;
    const double step = kInputFraction * std::max({span, std::abs(u), 1.0});
    // At a range's end the clamped side is the value itself (one-sided).
    double taken[2] = {u, u};
    const std::string what = "with input " + spec.name + " perturbed";
    difference(
        [&](double sign) {
          const double v = u + sign * step;
          const bool inside = !(spec.min < spec.max) || (v >= spec.min && v <= spec.max);
          taken[sign > 0 ? 0 : 1] = sim.set_input(input, inside ? v : u);
        },
        1.0, what.c_str(), gamma, d, g_u, k, true);
    const double width = taken[0] - taken[1];
    if (!(width > 0.0))
      throw SimulationError(out.t, out.step,
                            "linearize: input '" + spec.name + "' cannot be moved from " +
                                short_number(u) + " " + spec.unit + " within its range");
    gamma.col(k) /= width;
    d.col(k) /= width;
    g_u.col(k) /= width;
  }

  // The inverse of the trapezoidal rule's map: Phi = (I - hA/2)^-1 (I + hA/2),
  // Gamma = (I - hA/2)^-1 h B, so A = (2/h)(Phi + I)^-1 (Phi - I) and
  // B = (2/h)(Phi + I)^-1 Gamma ((Phi + I) and (Phi - I) commute). Solved in
  // units of the perturbations (S^-1 Phi S: pressures in Pa beside angles in
  // rad would span 1e12), then scaled back.
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd phi_scaled = widths.cwiseInverse().asDiagonal() * phi * widths.asDiagonal();
  const Eigen::PartialPivLU<Eigen::MatrixXd> plus(phi_scaled + identity);
  const Eigen::MatrixXd a_scaled = (2.0 / h) * plus.solve(phi_scaled - identity);
  // No inputs: B has no columns (and an empty solve reads a null matrix).
  const Eigen::MatrixXd b_scaled =
      m == 0 ? Eigen::MatrixXd(n, 0)
             : Eigen::MatrixXd((2.0 / h) * plus.solve(widths.cwiseInverse().asDiagonal() * gamma));
  out.A = widths.asDiagonal() * a_scaled * widths.cwiseInverse().asDiagonal();
  out.B = widths.asDiagonal() * b_scaled;
  if (!out.A.allFinite() || !out.B.allFinite())
    throw SimulationError(out.t, out.step,
                          "linearize: the step's map has an eigenvalue -1 (an oscillation at "
                          "the step's Nyquist frequency): no continuous A maps to it");
  // The formulation's outputs are written at accept only: from the step,
  // Y_{k+1} = C Phi X_k + (C Gamma + D) u, C by least squares (Phi is
  // nearly singular along the directions a projection removes).
  for (Eigen::Index k = 0; k < p; ++k) {
    if (!refs[static_cast<size_t>(k)].formulation) continue;
    const Eigen::VectorXd row =
        phi.transpose().completeOrthogonalDecomposition().solve(g_x.row(k).transpose());
    c.row(k) = row.transpose();
    d.row(k) = g_u.row(k) - row.transpose() * gamma;
  }
  out.Phi = phi;
  out.Gamma = gamma;
  out.C = c;
  out.D = d;
  return out;
}

namespace {

// Balancing (Parlett and Reinsch, Numer. Math. 13, 1969): the similarity
// D^-1 A D with D diagonal, in powers of two (so exact), that brings each
// state's row and column to similar norms. A's entries span twenty decades
// (radians beside pascals: 1e-13 to 1e9 on the four-bar), and without it the
// QR iteration loses the slow eigenvalues to rounding (a closed loop's -1.1
// 1/s came out +4.2).
Eigen::MatrixXd balanced(Eigen::MatrixXd b) {
  const Eigen::Index n = b.rows();
  for (bool done = false; !done;) {
    done = true;
    for (Eigen::Index i = 0; i < n; ++i) {
      double c = 0.0, r = 0.0;
      for (Eigen::Index j = 0; j < n; ++j)
        if (j != i) {
          c += std::abs(b(j, i));
          r += std::abs(b(i, j));
        }
      if (c == 0.0 || r == 0.0) continue;
      const double sum = c + r;
      double f = 1.0;
      while (c < r / 2.0) {
        f *= 2.0;
        c *= 4.0;
      }
      while (c >= r * 2.0) {
        f /= 2.0;
        c /= 4.0;
      }
      if ((c + r) / f < 0.95 * sum) {
        done = false;
        b.row(i) /= f;
        b.col(i) *= f;
      }
    }
  }
  return b;
}

}  // namespace

std::vector<std::complex<double>> eigenvalues(const Eigen::MatrixXd& a) {
  std::vector<std::complex<double>> values;
  if (a.size() == 0) return values;
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(balanced(a), false);
  const Eigen::VectorXcd& v = solver.eigenvalues();
  values.assign(v.data(), v.data() + v.size());
  std::sort(values.begin(), values.end(),
            [](const std::complex<double>& x, const std::complex<double>& y) {
              return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag();
            });
  return values;
}

}  // namespace mh
