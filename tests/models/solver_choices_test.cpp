// The solver's choices (solver.linear, solver.newton, solver.line_search)
// change how the step's equations are solved, not which: on both case
// studies, every linear solver gives KLU's trajectory to round-off; per-step
// Newton (the default) gives full Newton's within the Newton tolerances with
// one tangent per step, also on free mechanisms; modified Newton gives full
// Newton's within the tolerances (on a free mechanism, with no hydraulics to
// damp its error, only with a tolerance near round-off), and the line search
// leaves it as it is; on a stiff relief circuit where full Newton cycles, the
// line search converges to the valve's closed-form pressure.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "monohydra/core/input_error.hpp"
#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {
namespace {

struct Trajectory {
  std::vector<Eigen::VectorXd> z, y;  // coordinates and states, every 10 ms
  double iterations = 0.0;            // Newton iterations per step
  double tangents = 0.0;              // tangents factored per step
  double tol_state_scale = 0.0;       // the largest state tolerance (e.g. Pa)
};

Trajectory run(const std::string& model, const std::string& formulation,
               const std::function<void(SolverSettings&)>& choose, double t_end = 10.0) {
  ModelFile file = load_model_file(source_path("models/" + model));
  choose(file.solver);
  Simulation sim(file, build_plugins(), RunChoices{formulation, "", 1e-3, t_end});
  sim.start();
  Trajectory tr;
  const long steps = std::lround(t_end / 1e-3);
  long iterations = 0, tangents = 0;
  for (long k = 1; k <= steps; ++k) {
    sim.step();
    iterations += sim.last_step().iterations;
    tangents += sim.last_step().tangents;
    if (k % 10 != 0) continue;
    tr.z.push_back(sim.z());
    tr.y.push_back(sim.states());
  }
  tr.iterations = static_cast<double>(iterations) / static_cast<double>(steps);
  tr.tangents = static_cast<double>(tangents) / static_cast<double>(steps);
  return tr;
}

// max over the run of |a - b|_inf for coordinates and for the states relative
// to their magnitude.
struct Gap {
  double z = 0.0, y_rel = 0.0;
};
Gap gap(const Trajectory& a, const Trajectory& b) {
  Gap g;
  EXPECT_EQ(a.z.size(), b.z.size());
  for (size_t i = 0; i < a.z.size() && i < b.z.size(); ++i) {
    g.z = std::max(g.z, (a.z[i] - b.z[i]).lpNorm<Eigen::Infinity>());
    const double scale = std::max(1.0, a.y[i].lpNorm<Eigen::Infinity>());
    g.y_rel = std::max(g.y_rel, (a.y[i] - b.y[i]).lpNorm<Eigen::Infinity>() / scale);
  }
  return g;
}

struct Case {
  const char* model;
  const char* formulation;
};
constexpr Case kCases[] = {{"fourbar.yaml", "double-step"},
                           {"fourbar.yaml", "penalty"},
                           {"quickreturn.yaml", "double-step"},
                           {"quickreturn.yaml", "penalty"}};

TEST(SolverChoices, UmfpackAndDenseLuGiveKlusCaseStudyTrajectoriesToRoundOff) {
  for (const Case& c : kCases) {
    const Trajectory klu = run(c.model, c.formulation, [](SolverSettings&) {});
    for (LinearSolverKind kind : {LinearSolverKind::umfpack, LinearSolverKind::dense}) {
      const Trajectory other =
          run(c.model, c.formulation, [&](SolverSettings& s) { s.linear = kind; });
      const Gap g = gap(klu, other);
      // Round-off in the solve (1e-16 relative) propagated through 10 000
      // steps: far below the Newton tolerance (1e-7 rad) on every coordinate.
      EXPECT_LT(g.z, 1e-11) << c.model << ' ' << c.formulation << ' ' << to_string(kind);
      EXPECT_LT(g.y_rel, 1e-9) << c.model << ' ' << c.formulation << ' ' << to_string(kind);
      EXPECT_NEAR(other.iterations, klu.iterations, 1e-3)
          << c.model << ' ' << c.formulation << ' ' << to_string(kind);
    }
  }
}

TEST(SolverChoices, PerStepNewtonGivesFullNewtonsCaseStudyTrajectoriesWithOneTangentPerStep) {
  for (const Case& c : kCases) {
    const Trajectory full =
        run(c.model, c.formulation, [](SolverSettings& s) { s.newton = NewtonKind::full; });
    const Trajectory per_step =
        run(c.model, c.formulation, [](SolverSettings& s) { s.newton = NewtonKind::per_step; });
    const Gap g = gap(full, per_step);
    const std::string what = std::string(c.model) + " " + c.formulation;
    // Both solve every step to the same increment tolerance, and per-step
    // Newton's accepted iterate is a fast chord's (rate ~1e-2): the
    // coordinates stay within a tenth of the tolerance (1e-7 rad) over the
    // 10 s, the pressures within 1e-7 of their magnitude.
    EXPECT_LT(g.z, 1e-8) << what;
    EXPECT_LT(g.y_rel, 1e-7) << what;
    // One tangent a step (a second only where the chord contracts slowly),
    // against full Newton's one per iteration, for at most a quarter of an
    // iteration more per step.
    EXPECT_GE(per_step.tangents, 1.0) << what;
    EXPECT_LT(per_step.tangents, 1.01) << what;
    EXPECT_GT(full.tangents, 1.5) << what;
    EXPECT_LT(per_step.iterations, full.iterations + 0.25) << what;
  }
}

TEST(SolverChoices, ModifiedNewtonGivesFullNewtonsCaseStudyTrajectoriesWithinTheTolerances) {
  for (const Case& c : kCases) {
    const Trajectory full =
        run(c.model, c.formulation, [](SolverSettings& s) { s.newton = NewtonKind::full; });
    const Trajectory modified =
        run(c.model, c.formulation, [](SolverSettings& s) { s.newton = NewtonKind::modified; });
    const Gap g = gap(full, modified);
    const std::string what = std::string(c.model) + " " + c.formulation;
    // Every step of either is solved to the same increment tolerance; the
    // coordinates stay within one tolerance (1e-7 rad) over the 10 s. The
    // pressures (1e-2 Pa per step) drift apart by up to 1e-6 of their
    // magnitude (about 10 Pa of 4 MPa, the oscillating valve flows
    // accumulating the per-step differences over 10 000 steps).
    EXPECT_LT(g.z, 1e-7) << what;
    EXPECT_LT(g.y_rel, 1e-5) << what;
    // And it does keep its factorization: a tangent every few steps, not two
    // per step, for at most half an iteration more per step.
    EXPECT_LT(modified.tangents, 0.25) << what;
    EXPECT_GT(full.tangents, 1.5) << what;
    EXPECT_LT(modified.iterations, full.iterations + 0.5) << what;
  }
}

TEST(SolverChoices, LineSearchLeavesTheCaseStudiesAsFullNewtonSolvesThem) {
  for (const Case& c : kCases) {
    const Trajectory full = run(
        c.model, c.formulation, [](SolverSettings& s) { s.newton = NewtonKind::full; }, 2.0);
    const Trajectory damped = run(
        c.model, c.formulation,
        [](SolverSettings& s) {
          s.newton = NewtonKind::full;
          s.line_search = true;
        },
        2.0);
    const Gap g = gap(full, damped);
    const std::string what = std::string(c.model) + " " + c.formulation;
    // Every full increment passes the monotonicity test here: the same
    // iterates, bit for bit.
    EXPECT_EQ(g.z, 0.0) << what;
    EXPECT_EQ(g.y_rel, 0.0) << what;
    EXPECT_EQ(damped.iterations, full.iterations) << what;
  }
}

TEST(SolverChoices, LineSearchSolvesAStiffReliefCircuitWherePlainNewtonCycles) {
  const auto simulate = [](bool line_search, int halvings, int& max_iterations, long& damped,
                           long& retries) {
    ModelFile file = load_model_file(source_path("tests/fixtures/check/stiff-relief.yaml"));
    file.solver.line_search = line_search;
    file.solver.newton = NewtonKind::full;
    file.solver.max_step_halvings = halvings;
    Simulation sim(file, build_plugins());
    sim.start();
    for (int k = 0; k < 500; ++k) {
      sim.step();
      max_iterations = std::max(max_iterations, sim.last_step().iterations);
      damped += sim.last_step().damped;
      retries += sim.last_step().retries;
    }
    const auto& names = sim.state_names();
    const auto n = std::find(names.begin(), names.end(), "n") - names.begin();
    return sim.states()[n];
  };
  int its = 0;
  long damped = 0, retries = 0;
  // Plain Newton fails the first step: 25 iterations without converging.
  EXPECT_THROW(simulate(false, 0, its, damped, retries), SimulationError);
  its = 0;
  const double p = simulate(true, 0, its, damped, retries);
  // At rest the valve passes the pump's flow, its nominal flow, which it
  // passes at the nominal drop cracking + override: p = 1e5 + 1.5e7 + 5e5 Pa.
  EXPECT_NEAR(p, 1.56e7, 1.0);
  EXPECT_GT(damped, 0);
  EXPECT_EQ(retries, 0);
  EXPECT_LE(its, 12);
  // Step halving rescues plain Newton too, at 20 halvings and up to 93
  // iterations in one step; to the same pressure.
  int its_halved = 0;
  long damped_halved = 0, retries_halved = 0;
  const double p_halved = simulate(false, 10, its_halved, damped_halved, retries_halved);
  EXPECT_NEAR(p_halved, p, 1.0);
  EXPECT_GT(retries_halved, 0);
  EXPECT_GT(its_halved, 2 * its);
}

// A falling chain of 16 beams, where the tangent changes fast (the bench's
// chain): modified Newton keeps its energy balance as full Newton does, and
// still factors on fewer than half of the steps; per-step Newton keeps it too,
// factoring once a step.
TEST(SolverChoices, ModifiedNewtonKeepsAFallingChainsEnergyBalanceAsFullNewtonDoes) {
  std::string text = "units: {length: m, mass: kg, time: s, angle: deg}\nbodies:\n";
  for (int j = 0; j < 16; ++j)
    text += "  - {name: b" + std::to_string(j) +
            ", parent: " + (j == 0 ? std::string("ground") : "b" + std::to_string(j - 1)) +
            ", joint: {type: revolute, at: [" + (j == 0 ? "0" : "0.1") +
            ", 0, 0], axis: [0, 0, 1]}, mass: 1, shape: {type: beam, length: 0.1}, z0: 1}\n";
  text += "formulation: open-loop\nsolver: {dt: 0.001, t_end: 1}\n";
  struct Result {
    double drift = 0.0, ke = 0.0, tangents = 0.0;
  };
  const auto run_chain = [&](NewtonKind newton) {
    ModelFile file = parse_model_text(text, "chain.yaml");
    file.solver.newton = newton;
    Simulation sim(file, build_plugins());
    sim.start();
    Result r;
    for (int k = 0; k < 1000; ++k) {
      sim.step();
      r.drift = std::max(r.drift, std::abs(sim.drift()));
      r.ke = std::max(r.ke, sim.kinetic_energy());
      r.tangents += sim.last_step().tangents / 1000.0;
    }
    return r;
  };
  const Result full = run_chain(NewtonKind::full);
  const Result modified = run_chain(NewtonKind::modified);
  const Result per_step = run_chain(NewtonKind::per_step);
  EXPECT_NEAR(per_step.ke, full.ke, 1e-6 * full.ke);
  EXPECT_LT(per_step.drift, 1.01 * full.drift);
  EXPECT_NEAR(per_step.tangents, 1.0, 1e-9);
  EXPECT_GT(full.ke, 100.0);  // it falls: over 100 J of kinetic energy
  EXPECT_NEAR(modified.ke, full.ke, 1e-4 * full.ke);
  // The trapezoidal rule's own energy error (about 1e-4 of the kinetic
  // energy here) is what bounds the drift; modified Newton adds little to it.
  EXPECT_LT(full.drift, 2e-4 * full.ke);
  EXPECT_LT(modified.drift, 1.1 * full.drift);
  EXPECT_LT(modified.tangents, 0.5);
}

}  // namespace
}  // namespace mh::test

namespace mh::test {
namespace {

// Modified Newton's accepted iterate carries the error of a linear
// contraction, which the trapezoidal rule's rates (2/h and 4/h^2 times the
// position's error) pass from step to step undamped; full Newton's is the
// square of its last increment. So on a free mechanism, with no hydraulics to
// damp it, modified Newton holds the energy as full Newton does only with a
// position tolerance near round-off (at the default 1e-7 the free four-bar
// drifts 47.7 J in 10 s, against full Newton's 0.0126 J: docs/model-format.md).
TEST(SolverChoices, ModifiedNewtonNeedsARoundOffToleranceToHoldAFreeFourBarsEnergy) {
  const auto peak_drift = [](NewtonKind newton, double tol) {
    ModelFile file = load_model_file(source_path("models/fourbar-free.yaml"));
    file.solver.newton = newton;
    file.solver.tol_position = tol;
    Simulation sim(file, build_plugins(), RunChoices{"double-step", "", {}, {}});
    sim.start();
    double drift = 0.0;
    for (int k = 0; k < 10000; ++k) {
      sim.step();
      drift = std::max(drift, std::abs(sim.drift()));
    }
    return drift;
  };
  const double full = peak_drift(NewtonKind::full, 1e-7);
  EXPECT_LT(full, 0.02);  // J, of a kinetic energy up to 11 kJ
  EXPECT_LT(peak_drift(NewtonKind::modified, 1e-13), 1.1 * full);
  // Per-step Newton, the default, needs no such tolerance: its tangent is a
  // step's motion from exact, so its error is of the order of full Newton's.
  EXPECT_LT(peak_drift(NewtonKind::per_step, 1e-7), 1.1 * full);
}

}  // namespace
}  // namespace mh::test

namespace mh::test {
namespace {

// A chain of n beams (the bench's), open-loop.
std::string beam_chain(int n) {
  std::string text = "units: {length: m, mass: kg, time: s, angle: deg}\nbodies:\n";
  for (int j = 0; j < n; ++j)
    text += "  - {name: b" + std::to_string(j) +
            ", parent: " + (j == 0 ? std::string("ground") : "b" + std::to_string(j - 1)) +
            ", joint: {type: revolute, at: [" + (j == 0 ? "0" : "0.1") +
            ", 0, 0], axis: [0, 0, 1]}, mass: 1, shape: {type: beam, length: 0.1}, z0: 1}\n";
  return text + "formulation: open-loop\nsolver: {dt: 0.001, t_end: 1}\n";
}

struct ChainRun {
  double drift = 0.0, ke = 0.0, iterations = 0.0, tangents = 0.0;
  Eigen::VectorXd z;
};

ChainRun run_chain(const std::string& text, NewtonKind newton, int steps) {
  ModelFile file = parse_model_text(text, "chain.yaml");
  file.solver.newton = newton;
  Simulation sim(file, build_plugins());
  sim.start();
  ChainRun r;
  for (int k = 0; k < steps; ++k) {
    sim.step();
    r.drift = std::max(r.drift, std::abs(sim.drift()));
    r.ke = std::max(r.ke, sim.kinetic_energy());
    r.iterations += sim.last_step().iterations / static_cast<double>(steps);
    r.tangents += sim.last_step().tangents / static_cast<double>(steps);
  }
  r.z = sim.z();
  return r;
}

// Articulated Newton takes dxdd_dx M' for the tangent (its O(N) articulated
// factorization, no tangent assembled): the K and C it leaves out cost it
// iterations, not accuracy. Falling chains of 16 and 64 beams keep full
// Newton's energy balance and kinetic energy, in less than 2.5 times its
// iterations (measured: 4.8 and 4.4 against 2.0; each an O(N) solve in place
// of an O(N^3) one).
TEST(SolverChoices, ArticulatedNewtonKeepsFallingChainsEnergyAsFullNewtonDoes) {
  for (int n : {16, 64}) {
    const std::string text = beam_chain(n);
    const ChainRun full = run_chain(text, NewtonKind::full, 1000);
    const ChainRun articulated = run_chain(text, NewtonKind::articulated, 1000);
    EXPECT_GT(full.ke, 100.0) << n;  // it falls
    EXPECT_NEAR(articulated.ke, full.ke, 1e-4 * full.ke) << n;
    EXPECT_LT(articulated.drift, 1.1 * full.drift) << n;
    ::testing::Test::RecordProperty("iterations_full_" + std::to_string(n),
                                    scientific(full.iterations));
    ::testing::Test::RecordProperty("iterations_articulated_" + std::to_string(n),
                                    scientific(articulated.iterations));
    EXPECT_LT(articulated.iterations, 2.5 * full.iterations) << n;
    // One articulated factorization per iteration (counted as the step's
    // tangents), as cheap as a residual.
    EXPECT_DOUBLE_EQ(articulated.tangents, articulated.iterations) << n;
  }
}

// On the shipped double pendulum, released from the horizontal (chaotic
// later on, so 2 s of it), its coordinates stay as close to a reference
// solved to 1e-12 rad as full Newton's at the default 1e-7 (measured: 5.7e-9
// and 2.5e-9 rad; within 1e-8 both). Its error per
// step is a fraction of its last increment, and the trapezoidal rule passes
// a position error on to the velocities at 2/h: an increment that only met
// the tolerance would leave 2.4e-5 rad after 1 s (full Newton: 1e-9), which
// is why it iterates to 1e-4 of it.
TEST(SolverChoices, ArticulatedNewtonIsAsAccurateAsFullNewtonOnTheDoublePendulum) {
  ModelFile file = load_model_file(source_path("models/double-pendulum.yaml"));
  file.solver.t_end = 2.0;
  const auto run = [&](NewtonKind newton, double tol) {
    file.solver.newton = newton;
    file.solver.tol_position = tol;
    Simulation sim(file, build_plugins());
    sim.start();
    std::vector<Eigen::VectorXd> z;
    while (sim.time() < file.solver.t_end - 1e-9) {
      sim.step();
      z.push_back(sim.z());
    }
    return z;
  };
  const auto reference = run(NewtonKind::full, 1e-12);
  const auto full = run(NewtonKind::full, 1e-7);
  const auto articulated = run(NewtonKind::articulated, 1e-7);
  ASSERT_EQ(full.size(), reference.size());
  ASSERT_EQ(articulated.size(), reference.size());
  double full_error = 0.0, articulated_error = 0.0;
  for (size_t k = 0; k < full.size(); ++k) {
    full_error = std::max(full_error, (full[k] - reference[k]).lpNorm<Eigen::Infinity>());
    articulated_error =
        std::max(articulated_error, (articulated[k] - reference[k]).lpNorm<Eigen::Infinity>());
  }
  ::testing::Test::RecordProperty("full_error", scientific(full_error));
  ::testing::Test::RecordProperty("articulated_error", scientific(articulated_error));
  EXPECT_LT(full_error, 1e-8);
  EXPECT_LT(articulated_error, 1e-8);
}

// solver.newton: auto (the default) picks articulated Newton where it applies
// and the tree is deep (more than 6 mechanical entries a coordinate: a chain
// of 8 or more), per-step Newton otherwise; the run's settings say which.
TEST(SolverChoices, AutoNewtonIsArticulatedOnDeepChainsAndPerStepElsewhere) {
  const auto chosen = [](const ModelFile& file, const std::string& formulation) {
    Simulation sim(file, build_plugins(), RunChoices{formulation, "", {}, {}});
    return sim.settings().newton;
  };
  EXPECT_EQ(parse_model_text(beam_chain(8), "chain.yaml").solver.newton, NewtonKind::automatic);
  EXPECT_EQ(chosen(parse_model_text(beam_chain(4), "chain.yaml"), ""), NewtonKind::per_step);
  EXPECT_EQ(chosen(parse_model_text(beam_chain(8), "chain.yaml"), ""), NewtonKind::articulated);
  EXPECT_EQ(chosen(parse_model_text(beam_chain(64), "chain.yaml"), ""), NewtonKind::articulated);
  for (const char* model : {"double-pendulum.yaml", "maxwell-pendulum.yaml", "fourbar.yaml"})
    EXPECT_EQ(chosen(load_model_file(source_path(std::string("models/") + model)), ""),
              NewtonKind::per_step)
        << model;
  // A deep chain under a formulation without the equations of motion.
  EXPECT_EQ(chosen(parse_model_text(beam_chain(16), "chain.yaml"), "penalty"),
            NewtonKind::per_step);
}

// Where M' is not the tangent's leading part, or not all the unknowns are
// coordinates, it is refused at setup with the reason, at solver.newton.
TEST(SolverChoices, ArticulatedNewtonIsRefusedWhereItDoesNotApply) {
  const auto refusal = [](const std::string& model, const std::string& formulation) {
    ModelFile file = load_model_file(source_path("models/" + model));
    file.solver.newton = NewtonKind::articulated;
    try {
      Simulation sim(file, build_plugins(), RunChoices{formulation, "", {}, {}});
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("accepted");
  };
  const std::string ds = refusal("fourbar-free.yaml", "double-step");
  EXPECT_NE(
      ds.find("solver.newton: expected auto, full, per-step or modified here: articulated needs "
              "a formulation whose rows are the tree's equations of motion"),
      std::string::npos)
      << ds;
  EXPECT_NE(ds.find("formulation 'double-step' does not declare "
                    "monohydra.equations-of-motion/1"),
            std::string::npos)
      << ds;
  const std::string states = refusal("maxwell-pendulum.yaml", "");
  EXPECT_NE(states.find("articulated solves for the joint coordinates alone, and this model has 1 "
                        "subsystem state (e.g. 'holder.delta')"),
            std::string::npos)
      << states;
}

}  // namespace
}  // namespace mh::test
