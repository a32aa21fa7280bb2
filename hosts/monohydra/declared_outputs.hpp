// What a run's declared outputs say in words, for the comparison table: the
// coordinates a formulation had in use (outputs of kind MH_OUTPUT_COORDINATE,
// e.g. a partitioning formulation's independent coordinates) and its event counters
// (MH_OUTPUT_COUNTER, e.g. re-partitions). Nothing here knows a formulation.
#pragma once

#include <string>

#include "run_record.hpp"

namespace mh::cli {

// "z3 throughout", "z3 at start, changed at 2 steps", or "-" without such outputs.
std::string coordinates_in_use(const RunRecord& run);

// "repartitions 0, ..." (each counter's final value, by its column name
// without the instance prefix), or "-" without counters.
std::string counters_at_end(const RunRecord& run);

}  // namespace mh::cli
