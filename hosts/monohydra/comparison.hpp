// Several formulations' runs of one model and what is computed from them: the
// per-run metrics and each run's differences from the reference run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "run_metrics.hpp"
#include "run_record.hpp"

namespace mh::cli {

struct Comparison {
  std::string name;        // the model's (or case study's) name
  std::string model_path;  // as given
  std::vector<RunRecord> runs;
  std::vector<RunMetrics> metrics;  // parallel to runs
  // The reference of the differences: the first run, in the order asked, that
  // has rows (the first formulation unless it failed at setup); -1 when none.
  int reference = -1;
  std::vector<std::string> pressures;                   // the reference run's pressure columns
  std::vector<std::optional<Differences>> differences;  // parallel to runs; none without rows

  const RunRecord* reference_run() const {
    return reference < 0 ? nullptr : &runs[static_cast<size_t>(reference)];
  }
  bool any_failed() const;
};

Comparison summarize(std::string name, std::string model_path, std::vector<RunRecord> runs);

}  // namespace mh::cli
