// The double-step formulation (coordinate partitioning, Sects. 2.2 and 4): the
// paper's choice of independent coordinates, constraints held to round-off and
// energy conserved on the free four-bar and quick-return, re-partitioning
// before a partition turns singular, redundant constraints, and the clear
// stops that replace silent failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh {
namespace {

const char* const kSource = "formulation 'double-step'";

// The formulation's log lines, and the accepted step each one came in.
struct LogCapture {
  struct Line {
    mh_log_level level;
    std::string message;
    long step;  // steps accepted before it was logged
  };
  std::vector<Line> lines;
  long step = 0;
  LogSink sink() {
    return [this](mh_log_level level, const std::string& source, const std::string& message) {
      if (source == kSource) lines.push_back({level, message, step});
    };
  }
  bool has(mh_log_level level, const std::string& message) const {
    for (const auto& l : lines)
      if (l.level == level && l.message == message) return true;
    return false;
  }
  std::vector<Line> starting(const std::string& prefix) const {
    std::vector<Line> out;
    for (const auto& l : lines)
      if (l.message.rfind(prefix, 0) == 0) out.push_back(l);
    return out;
  }
  std::string all() const {
    std::string out;
    for (const auto& l : lines) out += "  [" + std::to_string(l.level) + "] " + l.message + "\n";
    return out;
  }
};

std::string model_text(const std::string& model) {
  std::ifstream in(test::source_path("models/" + model + ".yaml"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The model with `options` added to its double-step formulation block.
ModelFile with_options(const std::string& model, const std::string& options) {
  std::string text = model_text(model);
  const std::string block = "formulation: {name: double-step}";
  const size_t at = text.find(block);
  EXPECT_NE(at, std::string::npos) << model << " does not name double-step as its formulation";
  text.replace(at, block.size(), "formulation: {name: double-step, " + options + "}");
  return parse_model_text(text, model + ".yaml");
}

// What a run records, step by step.
struct Record {
  long steps = 0;
  bool failed = false;
  std::string failure;
  double max_phi = 0.0;
  double max_drift = 0.0;
  double max_ke = 0.0;  // max |KE - KE(0)|: the energy scale the drift is set against
  long iterations = 0;
  int max_iterations = 0;
  std::vector<double> t, z1, zd3;
};

Record record(Simulation& sim, LogCapture& log, double t_end) {
  Record rec;
  sim.start();
  try {
    while (sim.time() < t_end - 1e-9) {
      sim.step();
      log.step = sim.step_index();
      ++rec.steps;
      rec.max_phi = std::max(rec.max_phi, sim.phi_norm());
      rec.max_drift = std::max(rec.max_drift, std::abs(sim.drift()));
      rec.max_ke = std::max(rec.max_ke, std::abs(sim.kinetic_energy()));
      rec.iterations += sim.last_step().iterations;
      rec.max_iterations = std::max(rec.max_iterations, sim.last_step().iterations);
      rec.t.push_back(sim.time());
      rec.z1.push_back(sim.z()[0]);
      rec.zd3.push_back(sim.zd().size() > 2 ? sim.zd()[2] : 0.0);
    }
  } catch (const SimulationError& e) {
    rec.failed = true;
    rec.failure = e.what();
  }
  return rec;
}

void print(const char* what, const Record& r) {
  std::printf(
      "%s: %ld steps, Newton %.3f / %d iterations per step (avg / max), max phi_norm "
      "%.3e, peak |drift| %.3e J, max |KE - KE0| %.4g J\n",
      what, r.steps, static_cast<double>(r.iterations) / static_cast<double>(r.steps),
      r.max_iterations, r.max_phi, r.max_drift, r.max_ke);
}

// The 10 s free runs of the paper's mechanisms, made once and shared by the
// tests that assert different properties of them.
struct FreeRun {
  LogCapture log;
  Record rec;
  int unknowns = 0;
};

const FreeRun& free_run(const std::string& model) {
  static std::map<std::string, FreeRun> runs;
  auto it = runs.find(model);
  if (it != runs.end()) return it->second;
  FreeRun& run = runs[model];
  const ModelFile file = load_model_file(test::source_path("models/" + model + ".yaml"));
  EXPECT_DOUBLE_EQ(file.solver.dt, 1e-3);
  EXPECT_DOUBLE_EQ(file.solver.t_end, 10.0);
  Simulation sim(file, test::build_plugins(), "double-step", run.log.sink());
  run.unknowns = sim.num_mechanical_unknowns();
  run.rec = record(sim, run.log, file.solver.t_end);
  print(model.c_str(), run.rec);
  return run;
}

// -------------------------------------------------- choice of coordinates ----

TEST(DoubleStep, FullPivotingPicksZ3OnTheFourBarAndZ4OnTheQuickReturn) {
  // The paper (Sect. 5) reports z3 and z4; one degree of freedom each.
  for (const auto& [model, expected] : std::vector<std::pair<std::string, std::string>>{
           {"fourbar-free", "z3"}, {"quickreturn-free", "z4"}}) {
    LogCapture log;
    const ModelFile file = load_model_file(test::source_path("models/" + model + ".yaml"));
    Simulation sim(file, test::build_plugins(), "double-step", log.sink());
    EXPECT_TRUE(log.has(MH_LOG_INFO, "independent coordinates: " + expected))
        << model << " logged:\n"
        << log.all();
    EXPECT_EQ(sim.num_mechanical_unknowns(), 1) << model;
  }
}

// The dependent solve asks the host for Phi and Phi_z alone
// (MH_EVAL_POSITIONS_ONLY); the velocity term Phi_z_dot zd is evaluated only
// for the dynamics at the converged z, i.e. at most once per residual call
// (and for the accepted state's projections-free measure, never).
TEST(DoubleStep, DependentSolveEvaluatesTheConstraintVelocityTermOncePerResidualAtMost) {
  const ModelFile file = load_model_file(test::source_path("models/fourbar.yaml"));
  Simulation sim(file, test::build_plugins(), "double-step");
  sim.start();
  for (int k = 0; k < 1500; ++k) sim.step();  // the valve opens at t = 1 s: moving from there
  const Simulation::WorkCounters before = sim.counters();
  for (int k = 0; k < 500; ++k) sim.step();
  const Simulation::WorkCounters& c = sim.counters();
  const long residuals = c.residual_evaluations - before.residual_evaluations;
  const long rates = c.constraint_rate_passes - before.constraint_rate_passes;
  const long positions = c.constraint_position_passes - before.constraint_position_passes;
  std::printf(
      "[ measured ] 500 steps: %ld residuals, %ld Phi/Phi_z passes, %ld Phi_z_dot zd passes\n",
      residuals, positions, rates);
  EXPECT_GT(residuals, 500);
  EXPECT_LE(rates, residuals);
  // Without the bit every Phi evaluation would bring its velocity term.
  EXPECT_LT(rates, positions);
  // Each residual solves z^d from its estimate (one Phi evaluation at least)
  // and, unless the estimate is the solution to round-off, once more.
  EXPECT_GE(positions, residuals);
}

// ------------------------------------------------ the free mechanisms ----

TEST(DoubleStep, FreeFourBarHoldsItsConstraintsToRoundOffOverTenSeconds) {
  const FreeRun& run = free_run("fourbar-free");
  ASSERT_FALSE(run.rec.failed) << run.rec.failure;
  EXPECT_EQ(run.rec.steps, 10000);
  // z^d is solved to an increment of 1e-10 every residual, which by Newton's
  // quadratic convergence leaves round-off: measured max ||Phi|| 1.6e-15 m.
  EXPECT_LT(run.rec.max_phi, 1e-13);
  EXPECT_LE(run.rec.max_iterations, 2);
}

TEST(DoubleStep, FreeQuickReturnHoldsItsConstraintsToRoundOffOverTenSeconds) {
  const FreeRun& run = free_run("quickreturn-free");
  ASSERT_FALSE(run.rec.failed) << run.rec.failure;
  EXPECT_EQ(run.rec.steps, 10000);
  EXPECT_LT(run.rec.max_phi, 1e-13);  // measured 1.9e-15
  EXPECT_LE(run.rec.max_iterations, 2);
}

TEST(DoubleStep, FreeFourBarConservesEnergyOverTenSeconds) {
  const FreeRun& run = free_run("fourbar-free");
  ASSERT_FALSE(run.rec.failed) << run.rec.failure;
  // No subsystems: drift = KE + PE. The beams swing through ~1.1e4 J of kinetic
  // energy; the peak drift was 0.0127 J (1.2e-6 of it), nearly all gathered in
  // the fast first swing before t = 1.3 s.
  EXPECT_GT(run.rec.max_ke, 1e4);
  EXPECT_LT(run.rec.max_drift, 0.02);
  EXPECT_GT(run.rec.max_drift, 0.0);
}

TEST(DoubleStep, FreeQuickReturnConservesEnergyOverTenSeconds) {
  const FreeRun& run = free_run("quickreturn-free");
  ASSERT_FALSE(run.rec.failed) << run.rec.failure;
  // Peak drift measured 7.3e-3 J.
  EXPECT_LT(run.rec.max_drift, 0.01);
  EXPECT_GT(run.rec.max_drift, 0.0);
}

TEST(DoubleStep, FreeFourBarRepartitionsOnceBeforeBody1PassesTheVertical) {
  // With z3 independent, Phi_z^d holds the columns of z1 and z2, which are
  // parallel when O, C and E line up: body 1 pointing straight down
  // (z1 = -pi/2). The beam falls through there near t = 1.39 s, so the
  // partition must change before, and z1 is then the best choice for the rest.
  const FreeRun& run = free_run("fourbar-free");
  ASSERT_FALSE(run.rec.failed) << run.rec.failure;
  const auto events = run.log.starting("re-partitioned at t = ");
  ASSERT_EQ(events.size(), 1u) << run.log.all();
  EXPECT_EQ(events[0].level, MH_LOG_WARNING);
  EXPECT_EQ(events[0].message,
            "re-partitioned at t = 1.323 s: independent coordinates z1 (were z3)");
  const auto k = static_cast<size_t>(events[0].step);  // the index of the step that logged
  const double pi = std::acos(-1.0);
  EXPECT_GT(run.rec.z1[k], -pi / 2);  // not yet vertical
  size_t vertical = k;
  while (vertical < run.rec.z1.size() && run.rec.z1[vertical] > -pi / 2) ++vertical;
  ASSERT_LT(vertical, run.rec.z1.size());
  EXPECT_GT(run.rec.t[vertical] - run.rec.t[k], 0.03);  // measured 0.066 s ahead
  EXPECT_EQ(run.unknowns, 1);
}

// ---------------------------------------------------- the crank-rocker ----

TEST(DoubleStep, CrankRockerFullPivotingPicksTheCouplerAngleWhichNeverTurnsSingular) {
  // Full pivoting picks the coupler's relative angle z2. Its Phi_z^d (columns
  // of z1 and z3) is singular only when the coupler pin B lies on the ground
  // line through both pivots, which this Grashof linkage never reaches
  // (|OB| stays within 0.7 .. 1.3 m on the upper side): over a full crank turn
  // nothing needs re-partitioning.
  LogCapture log;
  const ModelFile file = load_model_file(test::source_path("models/crank-rocker.yaml"));
  Simulation sim(file, test::build_plugins(), "double-step", log.sink());
  EXPECT_TRUE(log.has(MH_LOG_INFO, "independent coordinates: z2")) << log.all();
  const Record rec = record(sim, log, 1.3);  // 2 pi / 5 rad/s = 1.257 s
  print("crank-rocker (z2)", rec);
  ASSERT_FALSE(rec.failed) << rec.failure;
  EXPECT_TRUE(log.starting("re-partitioned").empty()) << log.all();
  EXPECT_LT(rec.max_phi, 1e-13);
  // No gravity, so the drift is the change of the ~2.9 J kinetic energy:
  // measured 1.9e-4 J (6e-5 of it).
  EXPECT_LT(rec.max_drift, 5e-4);
}

TEST(DoubleStep, CrankRockerStartedOnTheRockerRepartitionsBeforeItsExtremePosition) {
  // With the rocker angle z3 independent, Phi_z^d (columns of z1 and z2) is
  // singular where crank and coupler line up: the rocker's extreme positions,
  // where zd3 changes sign (first near t = 0.434 s). The pivot ratio of
  // Phi_z^d falls by ~3e-3 per step there; at 0.1 the partition changes to the
  // crank angle z1 33 steps ahead, and the crank never turns singular.
  LogCapture log;
  const ModelFile file = with_options("crank-rocker", "independent_coordinates: z3");
  Simulation sim(file, test::build_plugins(), "", log.sink());
  EXPECT_TRUE(log.has(MH_LOG_INFO,
                      "independent coordinates: z3 (from the option independent_coordinates; "
                      "full pivoting picks z2)"))
      << log.all();
  const Record rec = record(sim, log, 1.0);
  print("crank-rocker (z3 first)", rec);
  ASSERT_FALSE(rec.failed) << rec.failure;
  const auto events = log.starting("re-partitioned at t = ");
  ASSERT_EQ(events.size(), 1u) << log.all();
  EXPECT_EQ(events[0].message,
            "re-partitioned at t = 0.401 s: independent coordinates z1 (were z3)");
  size_t extreme = 1;  // the first sign change of the rocker's rate
  while (extreme < rec.zd3.size() && rec.zd3[extreme] * rec.zd3[0] > 0.0) ++extreme;
  ASSERT_LT(extreme, rec.zd3.size());
  EXPECT_LT(events[0].step, static_cast<long>(extreme));
  EXPECT_LT(rec.max_phi, 1e-13);
  // Energy stays bounded through the switch: measured peak drift 2.4e-4 J of
  // ~2.9 J, close to the 1.9e-4 J of the coupler partition throughout.
  EXPECT_LT(rec.max_drift, 5e-4);
}

TEST(DoubleStep, CrossingALimitPositionWithinOneStepStopsWithAClearMessage) {
  // A threshold too low for the motion (1e-3 < the ~3e-3 the pivot ratio
  // moves per step) lets the rocker partition reach its singular configuration
  // unseen. det Phi_z^d then changes sign within a step; without the check the
  // run went on with a jump of 10 % of the kinetic energy. The step stops.
  LogCapture log;
  const ModelFile file =
      with_options("crank-rocker", "independent_coordinates: z3, repartition_rcond: 0.001");
  Simulation sim(file, test::build_plugins(), "", log.sink());
  const Record rec = record(sim, log, 1.0);
  ASSERT_TRUE(rec.failed);
  EXPECT_EQ(rec.failure,
            "t = 0.434 s, step 434: residual evaluation was discarded: formulation "
            "'double-step': the step to t = 0.434 s crosses a configuration where the partition "
            "with independent coordinates z3 is singular (det Phi_z^d changed sign): the "
            "re-partition check (repartition_rcond = 0.001) came too late; raise it or shorten "
            "the step");
  EXPECT_LT(rec.max_drift, 5e-4);  // it stopped before the energy jumped
}

// ------------------------------------------------- redundant constraints ----

TEST(DoubleStep, RedundantParallelogramDropsOneRowWithAWarningAndStillHoldsIt) {
  // Three parallel cranks under one coupler: 4 coordinates, 4 rows, rank 3.
  // The partition keeps 3 rows; the dropped one holds anyway (it is implied by
  // the others), so the host's phi_norm over all 4 rows stays at round-off.
  LogCapture log;
  const ModelFile file = load_model_file(test::source_path("models/parallelogram-redundant.yaml"));
  Simulation sim(file, test::build_plugins(), "double-step", log.sink());
  EXPECT_TRUE(log.has(MH_LOG_WARNING, "redundant constraints: using 3 of 4 rows (row 2 dropped)"))
      << log.all();
  EXPECT_EQ(sim.num_mechanical_unknowns(), 1);
  const Record rec = record(sim, log, 2.0);
  print("parallelogram-redundant", rec);
  ASSERT_FALSE(rec.failed) << rec.failure;
  EXPECT_LT(rec.max_phi, 1e-12);
  EXPECT_LT(rec.max_drift, 1e-3);
}

// ------------------------------------------------------------ refusals ----

TEST(DoubleStep, RefusesATreeAndNamesOpenLoop) {
  const ModelFile file = load_model_file(test::source_path("models/double-pendulum.yaml"));
  try {
    Simulation sim(file, test::build_plugins(), "double-step");
    FAIL() << "a tree was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "the model has no cut joints (0 constraint rows): double-step partitions the "
                  "coordinates of closed loops; use open-loop for a tree"),
              std::string::npos)
        << e.what();
  }
}

TEST(DoubleStep, AnIndependentCoordinateThatDoesNotExistIsAnOptionError) {
  const ModelFile file = with_options("fourbar-free", "independent_coordinates: z9");
  try {
    Simulation sim(file, test::build_plugins());
    FAIL() << "z9 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "formulation 'double-step' option 'independent_coordinates': expected 1 of "
                  "the coordinates z1, z2, z3, separated by commas (the mechanism has 1 degree "
                  "of freedom), got 'z9'"),
              std::string::npos)
        << e.what();
  }
}

// ------------------------------------------------------------ accuracy ----

TEST(DoubleStep, FourBarConvergesAtSecondOrder) {
  // z(0.5 s) of the free four-bar at dt = 4, 2 and 1 ms: halving dt quarters
  // the error of the trapezoidal rule on the reduced equations (Eqs. 32-35).
  std::vector<Eigen::VectorXd> z;
  for (double dt : {4e-3, 2e-3, 1e-3}) {
    ModelFile file = load_model_file(test::source_path("models/fourbar-free.yaml"));
    file.solver.dt = dt;
    file.solver.t_end = 0.5;
    Simulation sim(file, test::build_plugins(), "double-step");
    const RunSummary s = run(sim, nullptr);
    ASSERT_FALSE(s.failed) << s.failure;
    z.push_back(sim.z());
  }
  const double ratio = (z[0] - z[1]).norm() / (z[1] - z[2]).norm();
  std::printf("four-bar: error ratio at halved dt %.3f\n", ratio);
  EXPECT_NEAR(ratio, 4.0, 0.4);
}

// ------------------------------------------------------------- tangent ----

// The analytic tangent (every column given: the host's derivatives and the
// derivative of R_z) and the host's forward differences of the residual,
// against central differences of it, at the next step's iterate after `steps`
// steps of `dt`, in the block the formulation gives (its rows and columns;
// the subsystems' rows are the host's coupling, tested in
// tests/core/step/subsystem_coupling_test.cpp): the worst over its columns of
// max |J - J_cd| / max |J_cd|.
struct TangentErrors {
  double analytic = 0.0, forward = 0.0;
};

TangentErrors tangent_errors(const std::string& model, double dt, int steps) {
  ModelFile file = load_model_file(test::source_path("models/" + model + ".yaml"));
  file.solver.dt = dt;
  Simulation sim(file, test::build_plugins(), "double-step");
  sim.start();
  for (int i = 0; i < steps; ++i) sim.step();
  const Eigen::MatrixXd J = sim.assembled_tangent();
  const Eigen::MatrixXd J_fd = sim.finite_difference_tangent();
  const Eigen::MatrixXd J_cd = sim.central_difference_tangent();
  EXPECT_EQ(J.rows(), J_cd.rows());
  TangentErrors e;
  const int nm = sim.num_mechanical_unknowns();
  for (int c = 0; c < nm; ++c) {
    const auto cd = J_cd.col(c).head(nm);
    const double scale = cd.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0.0) << model << " column " << c;
    e.analytic = std::max(e.analytic, (J.col(c).head(nm) - cd).cwiseAbs().maxCoeff() / scale);
    e.forward = std::max(e.forward, (J_fd.col(c).head(nm) - cd).cwiseAbs().maxCoeff() / scale);
  }
  std::printf("%s (dt %g s, t %g s): vs central differences, analytic %.2e, forward %.2e\n",
              model.c_str(), dt, dt * steps, e.analytic, e.forward);
  return e;
}

TEST(DoubleStep, FourBarAnalyticTangentEqualsCentralDifferences) {
  for (double dt : {1e-3, 1e-2, 5e-2}) {
    const TangentErrors e = tangent_errors("fourbar", dt, static_cast<int>(std::lround(1.5 / dt)));
    EXPECT_LT(e.analytic, 1e-5);
  }
}

TEST(DoubleStep, QuickReturnAnalyticTangentEqualsCentralDifferences) {
  for (double dt : {1e-3, 1e-2, 5e-2}) {
    const TangentErrors e =
        tangent_errors("quickreturn", dt, static_cast<int>(std::lround(1.5 / dt)));
    EXPECT_LT(e.analytic, 1e-5);
  }
}

TEST(DoubleStep, FreeMechanismsAnalyticTangentEqualsCentralDifferences) {
  for (double dt : {1e-3, 1e-2, 5e-2}) {
    for (const char* model : {"fourbar-free", "quickreturn-free"}) {
      const TangentErrors e = tangent_errors(model, dt, static_cast<int>(std::lround(0.3 / dt)));
      EXPECT_LT(e.analytic, 1e-8);
    }
  }
}

// Three spatial loops closed by spherical joints: central differences of its
// residual carry an error of their own here (forward differences miss them by
// as much), so the analytic columns must be at least as close to them as the
// host's forward differences are.
TEST(DoubleStep, ExcavatorSpatialLoopsAnalyticTangentEqualsCentralDifferences) {
  for (double dt : {1e-3, 1e-2}) {
    const TangentErrors e =
        tangent_errors("excavator", dt, static_cast<int>(std::lround(0.5 / dt)));
    EXPECT_LT(e.analytic, 1.01 * e.forward + 1e-10);
    EXPECT_LT(e.analytic, 1e-3);
  }
}

}  // namespace
}  // namespace mh
