// The metrics a study keeps per case, computed from the run's columns (the
// same doubles as its CSV): run_metrics.hpp's peak drift, phi_norm and
// Newton iterations, the max, min or final value of any column, and the
// error against a reference run of the study.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "run_record.hpp"
#include "study_file.hpp"

namespace mh::cli::sweep {

// A reference run's times and the columns error metrics compare (read from
// its CSV by load_reference).
struct ReferenceRun {
  std::vector<double> t;
  std::map<std::string, std::vector<double>> columns;
};

// Reads the columns `names` (and t) of a run's CSV. Throws std::runtime_error.
ReferenceRun load_reference(const std::string& csv_path, const std::vector<std::string>& names);

// max over the run's rows of |x(t) - x_ref(t)|, x_ref interpolated linearly
// between the reference's rows (a reference with a finer step than the case
// has a row near every case row). nullopt when the reference lacks the
// column or does not cover the run's times.
std::optional<double> max_abs_error(const std::vector<double>& t, const std::vector<double>& x,
                                    const ReferenceRun& reference, const std::string& column);

// One value per metric of the study; an error (a column the run lacks) is
// thrown as std::invalid_argument. `references` maps a reference name to its
// run for this case's model (absent: the reference run failed: nullopt).
std::vector<std::optional<double>> case_metrics(
    const Study& study, const RunRecord& run,
    const std::map<std::string, const ReferenceRun*>& references);

}  // namespace mh::cli::sweep
