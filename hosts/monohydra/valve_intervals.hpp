// When the directional control valve is open, to shade those intervals in
// the report's time plots as the paper does (Sect. 6.1). Rule: a valve of
// type `valve-4-3` is open while the magnitude of its spool state U exceeds
// 1 % of the spool's full scale, 10 V (case-studies.md: U in -10 .. 10 V).
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "run_record.hpp"
#include "svg_plot.hpp"

namespace mh::cli {

inline constexpr const char* kValveType = "valve-4-3";
inline constexpr const char* kValveSpoolState = "U";
inline constexpr double kValveFullScale = 10.0;  // V
inline constexpr double kValveOpenFraction = 0.01;

// The CSV column of the spool state of every valve in the model, in model
// order: the name the file gives it under `states`, else "<subsystem>.U".
// A valve whose state is hidden (null in the file) has none.
std::vector<std::string> valve_columns(const ModelFile& file);

// The intervals [t_first, t_last] of consecutive rows in which any of the
// columns is open; merged, in time order. Columns the run lacks are ignored.
std::vector<PlotInterval> valve_open_intervals(const RunRecord& run,
                                               const std::vector<std::string>& columns);

}  // namespace mh::cli
