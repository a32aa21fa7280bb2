// The comparison as a table of text cells: one row per quantity, one column
// per formulation, and the paper's number beside each formulation when the
// model is one of the paper's case studies. Printed by render_text, and as
// HTML in the report.
#pragma once

#include <string>
#include <vector>

#include "case_studies.hpp"
#include "comparison.hpp"

namespace mh::cli {

struct TextTable {
  std::string title;
  std::vector<std::string> header;             // the first cell names the quantity column
  std::vector<std::vector<std::string>> rows;  // cells never empty ("-": nothing to show)
  std::vector<std::string> notes;              // lines after the table: failures, sources
};

// Row labels, as printed (docs/compare.md defines each quantity).
namespace row {
inline constexpr const char* kStatus = "status";
inline constexpr const char* kSteps = "steps";
inline constexpr const char* kAvgIterations = "Newton iterations avg";
inline constexpr const char* kMaxIterations = "Newton iterations max";
inline constexpr const char* kWall = "total wall time (s)";
inline constexpr const char* kPerStep = "time per step (ms)";
inline constexpr const char* kWorstStep = "worst step time (ms)";
inline constexpr const char* kWorstStepTime = "worst step at t (s)";
inline constexpr const char* kRealTime = "real-time factor";
inline constexpr const char* kDrift = "peak |drift| (J)";
inline constexpr const char* kDriftTime = "peak |drift| at t (s)";
inline constexpr const char* kWork = "max |W| (J)";
inline constexpr const char* kDriftPercent = "peak |drift| (% of max |W|)";
inline constexpr const char* kPhi = "max phi_norm";
inline constexpr const char* kPartition = "coordinates in use";
inline constexpr const char* kCounters = "events counted";
}  // namespace row

// `paper` may be null (then no paper columns).
TextTable comparison_table(const Comparison& c, const PaperNumbers* paper);

// Columns padded to their widest cell and separated by at least two spaces
// (cells hold single spaces at most), the title above, the notes below.
std::string render_text(const TextTable& table);

}  // namespace mh::cli
