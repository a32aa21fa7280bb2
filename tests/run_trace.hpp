// What a run shows after each step, recorded to compare two runs (or two
// continuations of one) entry by entry: the snapshot tests' yardstick.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "monohydra/core/simulation.hpp"

namespace mh::test {

struct RunTrace {
  std::vector<double> values;
  void record(const Simulation& sim) {
    values.push_back(sim.time());
    values.push_back(static_cast<double>(sim.step_index()));
    for (const Eigen::VectorXd* v :
         {&sim.z(), &sim.zd(), &sim.zdd(), &sim.states(), &sim.state_rates(), &sim.outputs()})
      values.insert(values.end(), v->data(), v->data() + v->size());
    values.push_back(sim.kinetic_energy());
    values.push_back(sim.potential_energy());
    values.push_back(sim.work());
    values.push_back(sim.stored_energy());
    values.push_back(sim.dissipated_energy());
    values.push_back(sim.phi_norm());
    values.push_back(static_cast<double>(sim.last_step().iterations));
    values.push_back(static_cast<double>(sim.counters().kinematics_passes));
    values.push_back(static_cast<double>(sim.counters().residual_evaluations));
    values.push_back(static_cast<double>(sim.counters().constraint_position_passes));
    values.push_back(static_cast<double>(sim.counters().constraint_rate_passes));
    values.push_back(static_cast<double>(sim.counters().derivative_passes));
  }
};

// `count` steps of `sim`, each recorded.
inline RunTrace trace_steps(Simulation& sim, int count) {
  RunTrace trace;
  for (int k = 0; k < count; ++k) {
    sim.step();
    trace.record(sim);
  }
  return trace;
}

// The largest difference of two traces, entry by entry (infinity when their
// lengths differ).
inline double largest_difference(const RunTrace& a, const RunTrace& b) {
  if (a.values.size() != b.values.size()) return HUGE_VAL;
  double d = 0.0;
  for (size_t i = 0; i < a.values.size(); ++i) d = std::max(d, std::abs(a.values[i] - b.values[i]));
  return d;
}

}  // namespace mh::test
