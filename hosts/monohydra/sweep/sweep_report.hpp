// The study's report (--report): DIR/report.html, one self-contained page in
// the style of compare's report (inline CSS and SVG, no scripts, well-formed
// XHTML), with the table and plots of each metric against each numeric
// varied parameter, and the study file's own plots (e.g. a work-precision
// diagram: error against CPU time). Each SVG is also written alone under
// DIR/figures/.
#pragma once

#include <string>
#include <vector>

#include "study_file.hpp"

namespace mh::cli::sweep {

struct SweepTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // in case order
};

// results.csv as read back. Throws std::runtime_error.
SweepTable read_table(const std::string& csv_path);

// The figures as <svg> elements: the study's plots first, then each metric
// against each numeric parameter. Points of a series share the model and the
// values of every other varied parameter that is not numeric; only ok rows
// are drawn. A log axis drops values <= 0.
std::vector<std::string> sweep_figures(const Study& study, const SweepTable& table);

// Writes DIR/report.html and DIR/figures/*.svg; returns the report's path.
std::string write_sweep_report(const std::string& dir, const Study& study, const SweepTable& table);

}  // namespace mh::cli::sweep
