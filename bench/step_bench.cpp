// Cost of the shared Newton step (trapezoidal unless named): whole 10 s runs of the shipped
// models (the target: 10 s at dt = 1 ms in at most 20 ms), and one step of an
// open chain of N bodies (the target: close to linear in N).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"

namespace {

const mh::PluginRegistry& plugins() {
  static const std::unique_ptr<mh::PluginRegistry> r = [] {
    auto p = std::make_unique<mh::PluginRegistry>();
    p->scan({MH_PLUGIN_DIR});
    return p;
  }();
  return *r;
}

void run_model(benchmark::State& state, const std::string& model, const std::string& formulation,
               const std::string& integrator = "") {
  const mh::ModelFile file = mh::load_model_file(std::string(MH_SOURCE_DIR) + "/models/" + model);
  long steps = 0, kinematics = 0, residuals = 0;
  for (auto _ : state) {
    mh::Simulation sim(file, plugins(), mh::RunChoices{formulation, integrator, {}, {}});
    const mh::RunSummary s = mh::run(sim, nullptr);
    if (s.failed) state.SkipWithError(s.failure.c_str());
    steps += s.steps;
    kinematics += sim.counters().kinematics_passes;
    residuals += sim.counters().residual_evaluations;
  }
  state.counters["steps"] = static_cast<double>(steps) / static_cast<double>(state.iterations());
  // Work per step: passes of the kinematics (target <= 6) and residual evaluations.
  state.counters["kinematics_passes"] =
      static_cast<double>(kinematics) / static_cast<double>(std::max(steps, 1L));
  state.counters["residuals"] =
      static_cast<double>(residuals) / static_cast<double>(std::max(steps, 1L));
  state.counters["time_per_step"] = benchmark::Counter(
      static_cast<double>(steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_DoublePendulum10s(benchmark::State& state) {
  run_model(state, "double-pendulum.yaml", "open-loop");
}
BENCHMARK(BM_DoublePendulum10s)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_MaxwellPendulum10s(benchmark::State& state) {
  run_model(state, "maxwell-pendulum.yaml", "open-loop");
}
BENCHMARK(BM_MaxwellPendulum10s)->Unit(benchmark::kMillisecond)->Iterations(3);

// The paper's case studies (Sect. 5): its Matlab took 21-29 s for each.
void BM_CaseStudy10s(benchmark::State& state, const char* model, const char* formulation) {
  run_model(state, model, formulation);
}
BENCHMARK_CAPTURE(BM_CaseStudy10s, fourbar_double_step, "fourbar.yaml", "double-step")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_CaseStudy10s, fourbar_penalty, "fourbar.yaml", "penalty")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_CaseStudy10s, quickreturn_double_step, "quickreturn.yaml", "double-step")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_CaseStudy10s, quickreturn_penalty, "quickreturn.yaml", "penalty")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// The same under the other shipped integrators (SDK 2.0): one step costs the
// same map and Newton iteration, so differences are in iterations per step.
void BM_CaseStudyIntegrator10s(benchmark::State& state, const char* model, const char* formulation,
                               const char* integrator) {
  run_model(state, model, formulation, integrator);
}
BENCHMARK_CAPTURE(BM_CaseStudyIntegrator10s, fourbar_penalty_generalized_alpha, "fourbar.yaml",
                  "penalty", "generalized-alpha")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_CaseStudyIntegrator10s, fourbar_penalty_bdf2, "fourbar.yaml", "penalty",
                  "bdf2")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// An open chain of N beams, each hinged at the previous one's tip.
std::string chain(int n) {
  std::string text = "units: {length: m, mass: kg, time: s, angle: deg}\nbodies:\n";
  for (int j = 0; j < n; ++j) {
    text += "  - name: b" + std::to_string(j) +
            "\n    parent: " + (j == 0 ? std::string("ground") : "b" + std::to_string(j - 1)) +
            "\n    joint: {type: revolute, at: [" + (j == 0 ? "0" : "0.1") +
            ", 0, 0], axis: [0, 0, 1]}\n    mass: 1\n    shape: {type: beam, length: 0.1}\n"
            "    z0: 1\n";
  }
  return text + "formulation: open-loop\nsolver: {dt: 0.001, t_end: 1}\n";
}

void BM_ChainStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const mh::ModelFile file = mh::parse_model_text(chain(n), "chain.yaml");
  mh::Simulation sim(file, plugins());
  sim.start();
  for (auto _ : state) sim.step();
  state.SetComplexityN(n);
}
BENCHMARK(BM_ChainStep)
    ->RangeMultiplier(2)
    ->Range(4, 64)
    ->Unit(benchmark::kMicrosecond)
    ->Complexity();

}  // namespace
