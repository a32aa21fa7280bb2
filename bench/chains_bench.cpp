// One step of generated mechanisms as they grow: the open chain of N beams
// (targets: 150 us per step at N = 64, 5 ms at N = 256) and a tree of
// bounded depth (one base, N/2 arms of two beams; target: linear in N), with
// per-step Newton (a tangent factored once a step), full Newton (one at every
// iteration, the paper's) and modified Newton (kept across steps), under every
// linear solver (auto: by the tangent's density); and articulated Newton (no
// tangent: the articulated-body recursion solves for the increment) and the
// default, solver.newton: auto, which is articulated Newton on the chains
// measured here from N = 8 (more than 6 tangent entries a coordinate,
// docs/model-format.md) and per-step Newton on the trees and shorter chains.
// A new simulation starts every simulated second (untimed), so every N is
// measured over the same motion; the energy error at that second, |KE + PE|
// (both relative to t = 0, J), is the accuracy simbody_chain_bench.cpp's peer
// reports beside its own. The chain goes on to N = 1024 (the peer's largest)
// and 2000 with the default linear solver and auto, the tree to 257, under
// every Newton kind: at N = 2000 a tangent-based step takes a few seconds
// (and as long again to set up), 5-10 s a benchmark.
#include <cmath>
#include <memory>

#include "bench_support.hpp"

namespace mh::bench {
namespace {

void step_model(benchmark::State& state, const std::string& text, LinearSolverKind linear,
                NewtonKind newton) {
  ModelFile file = parse_model_text(text, "generated.yaml");
  file.solver.linear = linear;
  file.solver.newton = newton;
  auto sim = std::make_unique<Simulation>(file, plugins());
  sim->start();
  double steps = 0, iterations = 0, tangents = 0, energy_error = -1;
  for (auto _ : state) {
    if (sim->time() >= 1.0 - 1e-9) {  // a new run (untimed): the same motion again
      state.PauseTiming();
      energy_error = std::abs(sim->kinetic_energy() + sim->potential_energy());
      sim = std::make_unique<Simulation>(file, plugins());
      sim->start();
      state.ResumeTiming();
    }
    try {
      sim->step();
    } catch (const std::exception& e) {  // a failed step ends the benchmark, said
      state.SkipWithError(e.what());
      break;
    }
    steps += 1;
    iterations += sim->last_step().iterations;
    tangents += sim->last_step().tangents;
  }
  step_counters(state, steps, iterations, tangents);
  // Negative when no simulated second was completed: the accuracy is unknown, not zero.
  state.counters["energy_error_1s"] = energy_error;
}

void add(const std::string& kind, int n, LinearSolverKind linear, NewtonKind newton) {
  const std::string name =
      kind + "/" + to_string(linear) + "/" + to_string(newton) + "/" + std::to_string(n);
  // Bodies: n for the chain; 1 + 2 arms for the tree (n odd).
  const std::string text = kind == "chain" ? chain(n) : tree((n - 1) / 2);
  benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& s) {
    step_model(s, text, linear, newton);
  })->Unit(benchmark::kMicrosecond);
}

const int registered = [] {
  for (NewtonKind newton : {NewtonKind::per_step, NewtonKind::full, NewtonKind::modified})
    for (LinearSolverKind linear : {LinearSolverKind::klu, LinearSolverKind::umfpack,
                                    LinearSolverKind::dense, LinearSolverKind::automatic}) {
      // KLU (the default) and auto (dense LU for the chain's dense tangent,
      // KLU for the tree's sparse one) to N = 1024 and 2000; the others on small N.
      const bool main = linear == LinearSolverKind::klu || linear == LinearSolverKind::automatic;
      for (int n : {2, 4, 8, 16, 32, 64, 128, 256, 1024, 2000})
        if (main || n <= 64) add("chain", n, linear, newton);
      for (int n : {5, 9, 17, 33, 65, 129, 257})
        if (main || n <= 33) add("tree", n, linear, newton);
    }
  // No tangent to factor: the linear solver is not used, KLU names the run.
  for (NewtonKind newton : {NewtonKind::articulated, NewtonKind::automatic}) {
    for (int n : {2, 4, 8, 16, 32, 64, 128, 256, 1024, 2000})
      add("chain", n, LinearSolverKind::klu, newton);
    for (int n : {5, 9, 17, 33, 65, 129, 257}) add("tree", n, LinearSolverKind::klu, newton);
  }
  return 0;
}();

}  // namespace
}  // namespace mh::bench
