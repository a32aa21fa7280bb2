// The contract checks of one component on one model, shared by the test
// host's API and `monohydra check` (through check_library): create/setup/
// destroy cycles, bad options refused, the analytic tangent against
// differences of the plugin's own residual, bit-identical reruns.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/testhost.hpp"

namespace mh::testhost {

// Steps of the small run each component is checked on: enough to leave the
// initial state, short enough for a plugin's whole check to take seconds.
constexpr int kSteps = 20;
// Create/setup/destroy cycles.
constexpr int kCycles = 3;
// The assembled tangent agrees with central differences when every entry is
// within this fraction of its own scale (TangentComparison says which).
constexpr double kTangentTolerance = 1e-3;
// An entry's scale is at least this fraction of the geometric mean of its
// row's and its column's largest difference, so an entry that should be zero
// may be off by kTangentTolerance x kEntryFloor = 1e-6 of that mean (the
// host's own forward-differenced blocks are about that good), yet a
// derivative in other units (d/dp ~ 1e-11 m^3/(s Pa) beside d/dzd ~ 1e-3 m^2)
// is compared at its own size.
constexpr double kEntryFloor = 1e-3;
// The coarse step of the second comparison: at least this, and 10 dt. At
// dt = 1 ms the trapezoidal rule's c_a = 4/dt^2 puts 4e6 M' in every
// mechanical row, hiding K and C at 1e-6; at 0.1 s, c_a = 400.
constexpr double kCoarseStep = 0.1;

struct Subject {
  ComponentKind kind;
  std::string id;
};

// The model a component is checked on and the choices that select it.
struct Setup {
  ModelFile file;
  RunChoices choices;
};

using Emit = std::function<void(const monohydra::testhost::Check&)>;

// Whether the model uses the subject (formulations and integrators: always,
// they replace the model's).
bool model_uses(const ModelFile& file, const Subject& who);

// The subject put into `file`: a formulation or an integrator replaces the
// model's own (keeping its options when it is the model's choice).
Setup setup_for(const ModelFile& file, const Subject& who);

// Run length: `steps` steps of the model's dt, no result file.
void shorten(Setup& s, int steps);

// The analytic tangent of a started run against central differences, at the
// model's dt and at the coarse step.
monohydra::testhost::TangentComparison compare_tangent(Simulation& sim);

// A formulation's own blocks dr/dx, dr/dxd, dr/dxdd against differences of
// its residual in each argument alone (Simulation::formulation_blocks): ""
// or the failure; `detail` says how many columns it gave and the worst.
std::string formulation_blocks_check(Simulation& sim, std::string& detail);

// Every check on the first of `candidates` the subject accepts (a
// formulation for trees only refuses the four-bar's cut joints with an input
// error, and gets the next); each line through `emit`.
void check_subject(const Subject& who, const std::vector<Setup>& candidates,
                   const PluginRegistry& registry, const Emit& emit);

}  // namespace mh::testhost
