// The cost of each step, not only the average: runs a model (or a generated
// chain or tree) to T_FROM, then steps it to T_TO and reports the mean and the
// largest wall time of one step, and the simulated time and Newton iterations
// of that largest one. Under valgrind --tool=callgrind --instr-atstart=no it
// also counts each step's instructions alone: instrumentation starts at
// T_FROM (the start-up and the run up to it go at valgrind's uninstrumented
// speed), and the counters are dumped after every step (or every EVERY
// steps), one file each, whose totals bench/performance.py reads (mean and
// largest).
//   mh_step_costs MODEL.yaml|chain:N|tree:N FORMULATION T_FROM T_TO
//   [auto|per-step|full|modified|articulated]
//                 [klu|umfpack|dense|auto] [EVERY]
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else  // without valgrind's header (Debian valgrind), times only
#define RUNNING_ON_VALGRIND 0
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_DUMP_STATS_AT(label) static_cast<void>(label)
#endif

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include "bench_support.hpp"

int main(int argc, char** argv) {
  using namespace mh;
  if (argc < 5 || argc > 8) {
    std::cerr << "usage: mh_step_costs MODEL.yaml|chain:N|tree:N FORMULATION T_FROM T_TO "
                 "[auto|per-step|full|modified|articulated] [klu|umfpack|dense|auto] [EVERY]\n";
    return 2;
  }
  try {
    const double t_from = std::stod(argv[3]), t_to = std::stod(argv[4]);
    const std::string newton = argc >= 6 ? argv[5] : "auto";
    const std::string linear = argc >= 7 ? argv[6] : "klu";
    const int every = argc >= 8 ? std::stoi(argv[7]) : 1;
    if (every < 1) throw std::runtime_error("EVERY: expected a positive number of steps");
    if (!(t_from >= 0.0 && t_to > t_from)) throw std::runtime_error("expected 0 <= T_FROM < T_TO");
    ModelFile file = bench::bench_model(argv[1]);
    bench::choose_solver(file, newton, linear);
    Simulation sim(file, bench::plugins(), RunChoices{argv[2], "", {}, t_to});
    sim.start();
    const double half_step = 0.5 * file.solver.dt;
    while (sim.time() < t_from - half_step) sim.step();
    const bool counting = RUNNING_ON_VALGRIND != 0;
    if (counting) {
      CALLGRIND_START_INSTRUMENTATION;
      CALLGRIND_DUMP_STATS_AT("before");  // the part before the first step, discarded
    }
    using clock = std::chrono::steady_clock;
    double total = 0.0, worst = 0.0, worst_at = 0.0;
    int steps = 0, worst_iterations = 0;
    char label[32];
    while (sim.time() < t_to - half_step) {
      const auto begin = clock::now();
      sim.step();
      const double seconds = std::chrono::duration<double>(clock::now() - begin).count();
      if (counting && (steps + 1) % every == 0) {
        std::snprintf(label, sizeof label, "step %d", steps);
        CALLGRIND_DUMP_STATS_AT(label);
      }
      total += seconds;
      ++steps;
      if (seconds > worst) {
        worst = seconds;
        worst_at = sim.time();
        worst_iterations = sim.last_step().iterations;
      }
    }
    std::cout << "steps " << steps << "\nmean_us " << 1e6 * total / std::max(steps, 1)
              << "\nworst_us " << 1e6 * worst << "\nworst_at " << worst_at << "\nworst_iterations "
              << worst_iterations << '\n';
  } catch (const std::exception& e) {
    std::cerr << "mh_step_costs: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
