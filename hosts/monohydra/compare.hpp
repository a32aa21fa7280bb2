// `monohydra compare`: several formulations on one model in one process, a
// table of their numbers side by side and, on request, a report with the
// paper's figures. Definitions: docs/compare.md.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "case_studies.hpp"
#include "monohydra/core/run_limits.hpp"

namespace mh::cli {

struct CompareJob {
  std::string model_path;
  std::vector<std::string> formulations;  // in order; the first is the reference
  std::string report_dir;                 // "" for no report and no CSVs
  std::optional<double> dt;               // override the model file's solver settings
  std::optional<double> t_end;
  RunLimits limits;                  // --max-steps, --max-output-bytes
  const CaseStudy* study = nullptr;  // the paper's numbers beside ours, when set
};

// Runs every formulation, prints the table to `out` (progress and failures to
// stderr) and writes the report. Returns 0, 1 when a formulation failed (it
// is in the table as failed, the others ran), 2 for bad input.
int run_comparison(const CompareJob& job, std::ostream& out);

}  // namespace mh::cli
