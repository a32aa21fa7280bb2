// One job of a study, run in a forked child the way `compare` isolates its
// runs (isolated_run.hpp): a case (its row comes back through a pipe) or a
// reference run (its CSV lands in DIR/references/). A case that crashes,
// fails or cannot be set up is a row with its status and reason; the study
// goes on.
#pragma once

#include <sys/types.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "case_expansion.hpp"
#include "case_metrics.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "results_table.hpp"
#include "study_file.hpp"

namespace mh::cli::sweep {

struct ReferenceJob {
  std::string name;
  int model = 0;
};

// What every process of a study shares: the study, its cases and
// references, the options, the plugins (scanned once, before the children
// are forked) and the reference runs' columns (read once, when the first
// case needs them).
struct SweepContext {
  Study study;
  std::vector<Case> cases;
  std::vector<ReferenceJob> references;
  std::string out_dir;
  std::optional<double> dt, t_end;  // --dt, --t-end: over the models, under a varied parameter
  bool keep_csv = false;
  PluginRegistry registry;
  std::map<std::pair<std::string, int>, std::optional<ReferenceRun>> loaded;

  std::string reference_csv(const ReferenceJob& r) const;
  std::string case_csv(int index) const;
};

// Builds the context: cases, references, plugins. Throws InputError.
void prepare_context(SweepContext& ctx);

// The model of `model` with the study's fixed values, --dt/--t-end, then
// `values`. Throws std::invalid_argument or InputError with the reason.
ModelFile case_model(const SweepContext& ctx, int model, const Overrides& values);

// A job: a case (index into ctx.cases) or a reference (index into ctx.references).
struct Job {
  bool reference = false;
  int index = 0;
};

// A job running in a child process.
struct RunningJob {
  Job job;
  pid_t pid = -1;
  int fd = -1;  // the child's message, read until end of file
  std::string message;
};

// Forks the child that runs `job` (references read before, for a case).
RunningJob start_job(SweepContext& ctx, const Job& job);
// Reads what the child sent; false at end of file (then call finish_job).
bool read_job(RunningJob& running);
// Waits for the child; for a case its row (a crash row when the child died),
// for a reference "" when it ran or the reason it did not.
std::string finish_job(SweepContext& ctx, RunningJob& running);
// The row's status field.
std::string row_status(const std::string& row, const Study& study);

// The case run in this process (what the child does).
CaseOutcome run_case(SweepContext& ctx, const Case& c);

}  // namespace mh::cli::sweep
