#include "declared_outputs.hpp"

#include <cmath>

#include "monohydra/types.h"

namespace mh::cli {
namespace {

std::vector<size_t> columns_of_kind(const RunRecord& run, uint32_t kind) {
  std::vector<size_t> out;
  for (size_t c = 0; c < run.info.size(); ++c)
    if (run.info[c].kind == kind && !run.info[c].qualified.empty()) out.push_back(c);
  return out;
}

// Coordinate k (1-based) is column k of the run: z1..zN follow t.
std::string coordinate_name(const RunRecord& run, double value) {
  const double k = std::round(value);
  if (!(k >= 1.0 && k <= run.num_coordinates)) return "?";
  return run.names[static_cast<size_t>(k)];
}

std::string formatted_count(double v) {
  return v == std::round(v) ? std::to_string(static_cast<long long>(v)) : std::to_string(v);
}

}  // namespace

std::string coordinates_in_use(const RunRecord& run) {
  const auto cols = columns_of_kind(run, MH_OUTPUT_COORDINATE);
  if (cols.empty() || run.rows() == 0) return "-";
  std::string first;
  for (size_t c : cols)
    first += (first.empty() ? "" : ", ") + coordinate_name(run, run.columns[c].front());
  int changes = 0;
  for (size_t k = 1; k < run.rows(); ++k) {
    bool changed = false;
    for (size_t c : cols) changed = changed || run.columns[c][k] != run.columns[c][k - 1];
    if (changed) ++changes;
  }
  if (changes == 0) return first + " throughout";
  return first + " at start, changed at " + std::to_string(changes) +
         (changes == 1 ? " step" : " steps");
}

std::string counters_at_end(const RunRecord& run) {
  const auto cols = columns_of_kind(run, MH_OUTPUT_COUNTER);
  if (cols.empty() || run.rows() == 0) return "-";
  std::string text;
  for (size_t c : cols) {
    const std::string& q = run.info[c].qualified;
    const auto dot = q.rfind('.');
    text += (text.empty() ? "" : ", ") + (dot == std::string::npos ? q : q.substr(dot + 1)) + " " +
            formatted_count(run.columns[c].back());
  }
  return text;
}

}  // namespace mh::cli
