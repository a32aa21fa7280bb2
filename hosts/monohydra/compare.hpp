// `monohydra compare`: several formulations and/or integrators on one model
// in one process, a table of their numbers side by side and, on request, a
// report with the paper's figures. Definitions: docs/compare.md.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "case_studies.hpp"
#include "monohydra/core/run_limits.hpp"
#include "step_overrides.hpp"

namespace mh::cli {

struct CompareJob {
  std::string model_path;
  // In order; every formulation runs with every integrator, the first pair is
  // the reference. Empty: the model file's compare defaults, else its own choice.
  std::vector<std::string> formulations;
  std::vector<std::string> integrators;
  std::string report_dir;            // "" for no report and no CSVs
  StepOverrides overrides;           // of the model file's solver settings
  const CaseStudy* study = nullptr;  // the paper's numbers beside ours, when set
  // `run --report`: one run, empty lists meaning the model file's own
  // formulation and integrator (not its compare lists).
  bool single_run = false;
};

// Runs every combination, prints the table to `out` (progress and failures to
// stderr) and writes the report (both also when runs fail). Returns 0 only
// when every run reached its end time, 1 when one failed (it is in the table
// as failed, the others ran), 2 for bad input.
int run_comparison(const CompareJob& job, std::ostream& out);

}  // namespace mh::cli
