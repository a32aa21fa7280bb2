// DIR/results.csv: one row per case, its parameters, status and metrics.
// Rows are appended as cases finish, each as one write of a whole line
// followed by fdatasync, so a study killed at any moment leaves whole rows
// (a torn last line, possible only if the machine itself stops, is cut off on
// resume). When every case has a row the file is rewritten in case order
// (a new file renamed over the old), so the table does not depend on which
// worker finished first.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "case_expansion.hpp"
#include "study_file.hpp"

namespace mh::cli::sweep {

// The columns whose values depend on the machine's load, not on the case.
inline const std::vector<std::string> kTimingColumns = {"cpu_s", "wall_s"};

// What a case gave: status ok (ran to t_end), failed (the simulation
// stopped: Newton, a plugin error), error (the case could not be set up: a
// bad parameter value, a missing column) or crashed (its process died).
struct CaseOutcome {
  std::string status;
  std::string reason;                          // "" when ok
  std::optional<double> t_reached;             // s, the time of the last row
  std::vector<std::optional<double>> metrics;  // parallel to Study::metrics
  double cpu_s = 0.0;                          // CPU time of the run (start and steps)
  double wall_s = 0.0;                         // wall time of the same
};

std::vector<std::string> table_columns(const Study& study);
// The row's first fields (case, model, parameters), which identify the case.
std::string row_prefix(const Study& study, const Case& c);
std::string format_row(const Study& study, const Case& c, const CaseOutcome& outcome);
// A field as CSV writes it: quoted when it holds a comma, quote or line break.
std::string csv_field(const std::string& text);
// Splits one CSV line (quoted fields allowed).
std::vector<std::string> split_csv_line(const std::string& line);

class ResultsTable {
 public:
  // Opens DIR/results.csv, creating it with the header, or reading the rows
  // it has, and locks it (flock). Throws std::runtime_error when it belongs to
  // another study (other columns, or a row whose parameters differ from that
  // case's) or another sweep holds it.
  ResultsTable(const std::string& dir, const Study& study, const std::vector<Case>& cases);
  ~ResultsTable();
  ResultsTable(const ResultsTable&) = delete;
  ResultsTable& operator=(const ResultsTable&) = delete;

  bool has(int case_index) const { return rows_.count(case_index) != 0; }
  std::size_t rows() const { return rows_.size(); }
  // Appends the row (a whole line, then fdatasync). Throws std::runtime_error.
  void append(int case_index, const std::string& row);
  // Rewrites the file in case order once every case has its row.
  void finish();
  const std::string& path() const { return path_; }
  const std::map<int, std::string>& row_texts() const { return rows_; }

 private:
  std::string path_;
  std::string header_;
  int fd_ = -1;
  std::map<int, std::string> rows_;
};

}  // namespace mh::cli::sweep
