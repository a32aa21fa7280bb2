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
// The assembled tangent agrees with forward differences when every entry is
// within this fraction of its row's largest difference (forward differences
// carry errors of about sqrt(machine epsilon) ~ 1e-8 relative, far below).
constexpr double kTangentTolerance = 1e-3;

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

// The analytic tangent of a started run against forward differences.
monohydra::testhost::TangentComparison compare_tangent(Simulation& sim);

// Every check on the first of `candidates` the subject accepts (a
// formulation for trees only refuses the four-bar's cut joints with an input
// error, and gets the next); each line through `emit`.
void check_subject(const Subject& who, const std::vector<Setup>& candidates,
                   const PluginRegistry& registry, const Emit& emit);

}  // namespace mh::testhost
