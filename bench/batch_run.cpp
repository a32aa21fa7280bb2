// A batch of runs of one model through the embedding API (mhs_batch_*):
// RUNS runs with parameters drawn uniformly (seeded) from the ranges given,
// stepped to T on THREADS threads. Prints the wall time of the stepping
// alone, and the process's resident memory after opening and after the
// first step (for the memory one more run adds: bench/batch_scaling.sh).
//
//   mh_batch_run MODEL RUNS THREADS T [PATH=LOW:HIGH ...]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "monohydra/simulation.h"

namespace {

// Resident set size (bytes) from /proc/self/statm.
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  statm >> pages >> resident;
  return resident * 4096.0;
}

struct Range {
  std::string path;
  double low = 0.0, high = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s MODEL RUNS THREADS T [PATH=LOW:HIGH ...]\n", argv[0]);
    return 2;
  }
  const unsigned runs = static_cast<unsigned>(std::stoul(argv[2]));
  const unsigned threads = static_cast<unsigned>(std::stoul(argv[3]));
  const double t_end = std::stod(argv[4]);
  std::vector<Range> ranges;
  for (int i = 5; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('='), colon = arg.find(':', eq);
    if (eq == std::string::npos || colon == std::string::npos) {
      std::fprintf(stderr, "%s: expected PATH=LOW:HIGH\n", argv[i]);
      return 2;
    }
    ranges.push_back({arg.substr(0, eq), std::stod(arg.substr(eq + 1, colon - eq - 1)),
                      std::stod(arg.substr(colon + 1))});
  }
  const double before = resident_bytes();
  mhs_batch* batch = nullptr;
  if (mhs_batch_open_file(argv[1], nullptr, 0, runs, threads, &batch) > MHS_WARNING) {
    std::fprintf(stderr, "%s\n", mhs_batch_message(batch));
    mhs_batch_free(batch);
    return 1;
  }
  std::mt19937 rng(20261207);
  for (unsigned k = 0; k < runs; ++k)
    for (const Range& r : ranges) {
      const double v = std::uniform_real_distribution<double>(r.low, r.high)(rng);
      if (mhs_batch_set_parameter(batch, k, r.path.c_str(), v) > MHS_WARNING) {
        std::fprintf(stderr, "%s\n", mhs_batch_message(batch));
        mhs_batch_free(batch);
        return 1;
      }
    }
  const double opened = resident_bytes();
  (void)mhs_batch_step(batch, 1);
  const double stepped = resident_bytes();
  const auto t0 = std::chrono::steady_clock::now();
  const mhs_status st = mhs_batch_advance(batch, t_end);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  uint32_t used = 0;
  (void)mhs_batch_size(batch, nullptr, &used);
  std::printf("runs %u threads %u t_end %g s: %.3f s stepping, status %d\n", runs, used, t_end,
              seconds, st);
  std::printf("resident: %.1f MB before, %.1f MB opened, %.1f MB after the first step\n",
              before / 1e6, opened / 1e6, stepped / 1e6);
  if (st != MHS_OK) std::printf("%s\n", mhs_batch_message(batch));
  mhs_batch_free(batch);
  return st == MHS_OK ? 0 : 1;
}
