// `monohydra sweep STUDY.yaml --out DIR [--jobs N] [--dt S] [--t-end S]
// [--report] [--keep-csv]` (docs/sweeps.md).
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

// 0 every case has its row (failed cases included), 1 the table could not be
// written, 2 bad usage or a bad study file, 128 + N stopped by signal N.
int run_sweep(const std::vector<std::string>& args);

}  // namespace mh::cli
