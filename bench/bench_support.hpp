// What the benchmarks share: the build's plugins, the shipped models, generated
// chains and trees, and the counters every run reports. Names are
// slash-separated fields (kind/model/formulation/integrator/linear/newton or
// kind/linear/newton/N) that bench/performance.py reads back.
#pragma once

#include <benchmark/benchmark.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh::bench {

namespace paths {
extern const char* const source_dir;  // the source tree (build_paths.cpp)
extern const char* const plugin_dir;  // this build's shipped plugins
}  // namespace paths

inline const PluginRegistry& plugins() {
  static const std::unique_ptr<PluginRegistry> r = [] {
    auto p = std::make_unique<PluginRegistry>();
    p->scan({paths::plugin_dir});
    return p;
  }();
  return *r;
}

inline ModelFile shipped_model(const std::string& name) {
  return load_model_file(std::string(paths::source_dir) + "/models/" + name);
}

// A body of the generated mechanisms: a 0.1 m, 1 kg beam hinged about z.
inline std::string beam(const std::string& name, const std::string& parent, double at,
                        double z0_deg) {
  return "  - name: " + name + "\n    parent: " + parent + "\n    joint: {type: revolute, at: [" +
         std::to_string(at) + ", 0, 0], axis: [0, 0, 1]}\n    mass: 1\n" +
         "    shape: {type: beam, length: 0.1}\n    z0: " + std::to_string(z0_deg) + "\n";
}

inline const char* kHeader = "units: {length: m, mass: kg, time: s, angle: deg}\nbodies:\n";
inline const char* kFooter = "formulation: open-loop\nsolver: {dt: 0.001, t_end: 1}\n";

// An open chain of n beams, each hinged at the previous one's tip.
inline std::string chain(int n) {
  std::string text = kHeader;
  for (int j = 0; j < n; ++j)
    text += beam("b" + std::to_string(j), j == 0 ? "ground" : "b" + std::to_string(j - 1),
                 j == 0 ? 0.0 : 0.1, 1.0);
  return text + kFooter;
}

// A tree of bounded depth: one base beam on the ground and `arms` arms of two
// beams each hinged at its tip, spread around it: 1 + 2 arms bodies, depth 3
// whatever their number.
inline std::string tree(int arms) {
  std::string text = kHeader;
  text += beam("base", "ground", 0.0, 1.0);
  for (int a = 0; a < arms; ++a) {
    const std::string id = std::to_string(a);
    text += beam("a" + id, "base", 0.1, 360.0 * a / arms);
    text += beam("c" + id, "a" + id, 0.1, 10.0);
  }
  return text + kFooter;
}

// A shipped model by file name, or a generated mechanism: chain:N or tree:N
// (N bodies, N odd for the tree), as mh_profile and mh_step_costs take them.
inline ModelFile bench_model(const std::string& what) {
  if (what.rfind("chain:", 0) == 0) return parse_model_text(chain(std::stoi(what.substr(6))), what);
  if (what.rfind("tree:", 0) == 0)
    return parse_model_text(tree((std::stoi(what.substr(5)) - 1) / 2), what);
  return shipped_model(what);
}

// The solver choices mh_profile and mh_step_costs take by name
// (auto|full|per-step|modified|articulated, klu|umfpack|dense|auto); throws
// std::runtime_error
// naming what it expected.
inline void choose_solver(ModelFile& file, const std::string& newton, const std::string& linear) {
  bool known = false;
  for (NewtonKind kind : {NewtonKind::full, NewtonKind::per_step, NewtonKind::modified,
                          NewtonKind::articulated, NewtonKind::automatic})
    if (newton == to_string(kind)) {
      file.solver.newton = kind;
      known = true;
    }
  if (!known)
    throw std::runtime_error(
        "newton: expected auto, full, per-step, modified or articulated, got '" + newton + "'");
  for (LinearSolverKind kind : {LinearSolverKind::klu, LinearSolverKind::umfpack,
                                LinearSolverKind::dense, LinearSolverKind::automatic})
    if (linear == to_string(kind)) {
      file.solver.linear = kind;
      return;
    }
  throw std::runtime_error("linear: expected klu, umfpack, dense or auto, got '" + linear + "'");
}

// Per-step counters of a run of `steps` steps in all the benchmark's iterations.
// Work per step: Newton iterations, tangents, passes of the kinematics (the
// target is at most 6) and residual evaluations.
inline void step_counters(benchmark::State& state, double steps, double iterations, double tangents,
                          double kinematics = -1, double residuals = -1) {
  state.counters["steps"] = steps / static_cast<double>(state.iterations());
  state.counters["us_per_step"] =
      benchmark::Counter(steps * 1e-6, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["its_per_step"] = iterations / steps;
  state.counters["tangents_per_step"] = tangents / steps;
  if (kinematics >= 0) state.counters["kinematics_passes"] = kinematics / steps;
  if (residuals >= 0) state.counters["residuals_per_step"] = residuals / steps;
}

}  // namespace mh::bench
