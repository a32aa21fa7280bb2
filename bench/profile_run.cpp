// One run for a profile (bench/performance.py runs it under valgrind
// --tool=callgrind): a shipped model, or a generated chain or tree, for a
// given simulated time, writing its CSV to /dev/null every step, every 10 ms
// or not at all.
//   mh_profile MODEL.yaml|chain:N|tree:N FORMULATION T_END [none|every-step|10ms]
//              [auto|per-step|full|modified|articulated] [klu|umfpack|dense|auto]
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

#include "bench_support.hpp"
#include "monohydra/core/csv_layout.hpp"

int main(int argc, char** argv) {
  using namespace mh;
  if (argc < 4 || argc > 7) {
    std::cerr << "usage: mh_profile MODEL.yaml|chain:N|tree:N FORMULATION T_END "
                 "[none|every-step|10ms] [auto|per-step|full|modified|articulated] "
                 "[klu|umfpack|dense|auto]\n";
    return 2;
  }
  try {
    const std::string what = argv[1];
    const std::string output = argc >= 5 ? argv[4] : "none";
    const std::string newton = argc >= 6 ? argv[5] : "auto";
    const std::string linear = argc >= 7 ? argv[6] : "klu";
    if (output != "none" && output != "every-step" && output != "10ms")
      throw std::runtime_error("output: expected none, every-step or 10ms, got '" + output + "'");
    ModelFile file = bench::bench_model(what);
    bench::choose_solver(file, newton, linear);
    Simulation sim(file, bench::plugins(), RunChoices{argv[2], "", {}, std::stod(argv[3])});
    const CsvLayout layout(sim, OutputSettings{},
                           output == "10ms" ? std::optional<double>(0.01) : std::nullopt);
    std::ofstream csv("/dev/null");
    RunOptions options;
    options.layout = &layout;
    const RunSummary s = run(sim, output == "none" ? nullptr : &csv, options);
    // The kind the run resolved (auto picks one at setup): bench/performance.py reads it.
    std::cout << s.steps << " steps, " << s.iterations << " Newton iterations, "
              << to_string(sim.settings().newton) << " Newton\n";
    if (s.failed) {
      std::cerr << "mh_profile: " << s.failure << '\n';
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "mh_profile: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
