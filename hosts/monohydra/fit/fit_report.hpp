// What `monohydra fit` says of its result: the estimates table (printed, and
// estimates.csv), the correlations, each column's residual RMS, and the
// report page: every measured column against the fitted and the initial
// model's predictions at its samples.
#pragma once

#include <string>
#include <vector>

#include "comparison_table.hpp"
#include "fit_statistics.hpp"
#include "least_squares.hpp"
#include "measured_data.hpp"
#include "sampled_run.hpp"

namespace mh::cli {

struct FitOutcome {
  const SampledRun* run = nullptr;
  const MeasuredData* data = nullptr;
  const FitResult* result = nullptr;
  const FitStatistics* statistics = nullptr;
  std::string model_path;
};

TextTable estimates_table(const FitOutcome& o);
TextTable correlation_table(const FitOutcome& o);
TextTable residual_table(const FitOutcome& o);  // per column: fitted, initial RMS and weight

// estimates.csv: path,initial,estimate,std_error,ci_low,ci_high,identifiable
// (empty error and interval for a parameter that is not identifiable).
std::string estimates_csv(const FitOutcome& o);
// report.html: standalone XHTML, the tables and one plot per measured column.
std::string fit_report_html(const FitOutcome& o);

}  // namespace mh::cli
