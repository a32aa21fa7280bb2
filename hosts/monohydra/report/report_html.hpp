// The comparison's report: one self-contained page (report.html: inline CSS,
// SVG and scripts, nothing from the network) that is also well-formed XML
// (polyglot XHTML), with the animated 3D view (machine_view.hpp), the table,
// every figure of report_figures and links to the runs' CSVs; each SVG is
// also written alone under figures/.
#pragma once

#include <string>
#include <vector>

#include "comparison.hpp"
#include "comparison_table.hpp"
#include "report_figures.hpp"

namespace mh::cli {

struct ReportPage {
  std::string title;
  std::vector<std::string>
      facts;  // lines under the title: model, settings, control-signal intervals
  const TextTable* table = nullptr;
  const std::vector<ReportFigure>* figures = nullptr;
  std::vector<std::string> csv_files;  // names relative to the report's folder
  std::string view;                    // machine_view_html's section, or "" for none
  std::string view_note;               // why there is none, said in its place
};

std::string report_html(const ReportPage& page);

// Writes DIR/report.html and DIR/figures/<svg id>.svg; returns the report's
// path. Throws std::runtime_error naming a file that cannot be written.
std::string write_report(const std::string& dir, const ReportPage& page);

}  // namespace mh::cli
