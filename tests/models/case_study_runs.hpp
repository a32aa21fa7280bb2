// The paper's two case studies run once per process and formulation, and
// recorded every 10 ms, for the tests of models/fourbar.yaml and
// models/quickreturn.yaml.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/core/simulation.hpp"
#include "test_support.hpp"

namespace mh::test {

struct CaseRun {
  std::vector<double> t;                // every 10 ms
  std::vector<Eigen::VectorXd> z;       // coordinates
  std::vector<Eigen::VectorXd> p;       // p1, p2, p3, U
  Eigen::VectorXd z0, p0;               // at t = 0
  double s0 = 0.0, Fs0 = 0.0;           // cylinder length and force at t = 0
  double still_z = 0.0, still_p = 0.0;  // max |z - z0|, |p - p0| before t = 1 s
  double max_drift = 0.0, t_max_drift = 0.0;
  double max_work = 0.0;  // max |W|
  double max_phi = 0.0;
  double iterations = 0.0;  // average per step
  int max_iterations = 0;
  // The coordinates the formulation declared in use (outputs of kind
  // MH_OUTPUT_COORDINATE) at t = 0, by name; how many steps changed them; its
  // counters (MH_OUTPUT_COUNTER) at the end.
  std::vector<std::string> coordinates_in_use;
  int coordinate_changes = 0;
  std::map<std::string, double> counters;
};

inline std::vector<int> pressure_columns(const Simulation& sim) {
  std::vector<int> cols;
  for (const char* name : {"p1", "p2", "p3", "U"}) cols.push_back(sim.state_index(name));
  return cols;
}

// Runs `model` with `formulation` at `dt` to `t_end`, recording every
// `record_every` seconds.
inline CaseRun run_case(const std::string& model, const std::string& formulation, double dt = 1e-3,
                        double t_end = 10.0, double record_every = 1e-2,
                        const std::string& integrator = "") {
  const ModelFile file = load_model_file(source_path("models/" + model));
  CaseRun r;
  Simulation sim(file, build_plugins(), RunChoices{formulation, integrator, dt, t_end});
  sim.start();
  std::vector<int> coordinate_outputs;
  for (size_t i = 0; i < sim.output_info().size(); ++i) {
    if (sim.output_info()[i].kind != MH_OUTPUT_COORDINATE) continue;
    coordinate_outputs.push_back(static_cast<int>(i));
    const double k = sim.outputs()[static_cast<Eigen::Index>(i)];
    r.coordinates_in_use.push_back(sim.coordinate_names()[static_cast<size_t>(k) - 1]);
  }
  Eigen::VectorXd in_use = sim.outputs();
  const std::vector<int> cols = pressure_columns(sim);
  const auto pressures = [&] {
    Eigen::VectorXd p(4);
    for (int i = 0; i < 4; ++i) p[i] = sim.states()[cols[static_cast<size_t>(i)]];
    return p;
  };
  r.z0 = sim.z();
  r.p0 = pressures();
  r.s0 = sim.outputs()[sim.output_index("s")];
  r.Fs0 = sim.outputs()[sim.output_index("Fs")];
  const long steps = std::lround(t_end / dt);
  const long every = std::max(1L, std::lround(record_every / dt));
  r.t.push_back(0.0);
  r.z.push_back(r.z0);
  r.p.push_back(r.p0);
  long total = 0;
  for (long k = 1; k <= steps; ++k) {
    sim.step();
    bool changed = false;
    for (int i : coordinate_outputs) changed = changed || sim.outputs()[i] != in_use[i];
    if (changed) ++r.coordinate_changes;
    in_use = sim.outputs();
    const int it = sim.last_step().iterations;
    total += it;
    r.max_iterations = std::max(r.max_iterations, it);
    const Eigen::VectorXd p = pressures();
    if (sim.time() < 1.0 - 0.5 * dt) {
      r.still_z = std::max(r.still_z, (sim.z() - r.z0).lpNorm<Eigen::Infinity>());
      r.still_p = std::max(r.still_p, (p - r.p0).lpNorm<Eigen::Infinity>());
    }
    if (std::abs(sim.drift()) > r.max_drift) {
      r.max_drift = std::abs(sim.drift());
      r.t_max_drift = sim.time();
    }
    r.max_work = std::max(r.max_work, std::abs(sim.work()));
    r.max_phi = std::max(r.max_phi, sim.phi_norm());
    if (k % every == 0) {
      r.t.push_back(sim.time());
      r.z.push_back(sim.z());
      r.p.push_back(p);
    }
  }
  r.iterations = static_cast<double>(total) / static_cast<double>(steps);
  for (size_t i = 0; i < sim.output_info().size(); ++i)
    if (sim.output_info()[i].kind == MH_OUTPUT_COUNTER)
      r.counters[sim.output_info()[i].qualified] = sim.outputs()[static_cast<Eigen::Index>(i)];
  return r;
}

// The 10 s work cycle at dt = 1 ms, run once per process.
inline const CaseRun& work_cycle(const std::string& model, const std::string& formulation) {
  static std::map<std::pair<std::string, std::string>, CaseRun> runs;
  auto key = std::make_pair(model, formulation);
  auto it = runs.find(key);
  if (it == runs.end()) it = runs.emplace(key, run_case(model, formulation)).first;
  return it->second;
}

}  // namespace mh::test
