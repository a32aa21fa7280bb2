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

// In a subsystem's derivative blocks (Simulation::subsystem_blocks) and a
// formulation's tangent blocks, an entry's scale floor is this fraction of
// its row's largest effect (an entry times its column's magnitude: what the
// column at its own size moves the row by) over its column's magnitude:
// rows and columns each in their own units and sizes, so a leakage's d/dp
// of 1e-15 m^3/(s Pa) beside a displacement's d/dx of 1e-3 is judged at its
// own size (its effect is 6e-4 of the row's largest), while an analytic
// entry's rounding residue (1e-10 of the row's largest effect where the
// differences are 0) passes.
constexpr double kBlockFloor = 1e-6;
// The blocks are compared at these instants of the model's own run: its
// prediction of the first step, after 3 steps, at a third and two thirds of
// it and at its last step, where valves and stops have changed regime; at
// most this many steps in (a long model's later instants come earlier).
constexpr int kBlockSteps = 2000;

struct Subject {
  ComponentKind kind;
  std::string id;
};

// The model a component is checked on and the choices that select it.
struct Setup {
  ModelFile file;
  RunChoices choices;
  std::vector<double> block_times;  // s: where the blocks are compared (CheckOptions::at)
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

// A formulation's own blocks dr/dx, dr/dxd, dr/dxdd at time t against
// differences of its residual in each argument alone
// (Simulation::formulation_blocks), at the blocks' floor (kBlockFloor): ""
// or the failure; `worst` raised to each block's worst entry.
std::string compare_formulation_blocks(const Simulation::FormulationBlocks& f, double t,
                                       double worst[3]);

// The steps of a model's run (at most kBlockSteps) after which a
// subsystem's blocks are compared: 0, 3, a third, two thirds, the last; or
// the steps nearest the setup's block_times.
std::vector<int> block_instants(const Setup& s);

// Each given block of an instance (at time t) against its differences,
// entry by entry: the failure (block, instance, time, row and column by
// name, both values) or ""; the worst entry; how many entries were
// compared, and how many nonzero ones have differences too noisy to judge
// a 1 % error by.
struct BlocksComparison {
  std::string failure;
  double worst = 0.0;  // of its scale
  int compared = 0, noisy = 0;
};
BlocksComparison compare_subsystem_blocks(const std::vector<Simulation::DerivativeBlock>& blocks,
                                          const std::string& instance, double t);

// A row's largest effect in one block: an entry of its differences times
// its column's magnitude (what the column at its own size moves the row by).
Eigen::VectorXd row_effect(const Simulation::TangentSample& t);
// The rows' largest effects over every argument (blocks with the same rows).
// Each block's entries are judged by their row's effect in that block, or
// by these where the row does not depend on the block's argument at all (a
// constraint row on the rates, whose analytic entries are rounding residues).
struct Effects {
  Eigen::VectorXd state_rows, force_rows;  // dR/..., dF/...
  const Eigen::VectorXd& of(const Simulation::DerivativeBlock& b) const {
    return b.name.rfind("dF", 0) == 0 ? force_rows : state_rows;
  }
};
Effects block_effects(const std::vector<Simulation::DerivativeBlock>& blocks);
Eigen::VectorXd formulation_effect(const Simulation::FormulationBlocks& f);
Eigen::VectorXd judged_effect(const Simulation::TangentSample& t, const Eigen::VectorXd& across);
// Whether a 1 % error of entry (r, c) of a block, its row's largest effect
// `effect`, would show above its scale: false where the differences are
// too noisy or the entry is below the floor.
bool shows_one_percent(const Simulation::TangentSample& t, Eigen::Index r, Eigen::Index c,
                       double effect);

// Every check on the first of `candidates` the subject accepts (a
// formulation for trees only refuses the four-bar's cut joints with an input
// error, and gets the next); each line through `emit`.
void check_subject(const Subject& who, const std::vector<Setup>& candidates,
                   const PluginRegistry& registry, const Emit& emit);

}  // namespace mh::testhost
