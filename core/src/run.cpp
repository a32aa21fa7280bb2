#include "monohydra/core/run.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>

namespace mh {
namespace {
// Shortest text that reads back as the same double: exact and fast.
void put(std::ostream& out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  out.write(buf, res.ptr - buf);
}
}  // namespace

void write_csv_header(std::ostream& out, const Simulation& sim) {
  out << "t";
  for (const auto& n : sim.coordinate_names()) out << ',' << n;
  for (const auto& n : sim.state_names())
    if (!n.empty()) out << ',' << n;
  for (const auto& n : sim.output_names())
    if (!n.empty()) out << ',' << n;
  out << ",KE,PE,W,drift,phi_norm,iters\n";
}

void write_csv_row(std::ostream& out, const Simulation& sim) {
  put(out, sim.time());
  for (int i = 0; i < sim.z().size(); ++i) {
    out << ',';
    put(out, sim.z()[i]);
  }
  const auto& state_names = sim.state_names();
  for (int i = 0; i < sim.states().size(); ++i) {
    if (state_names[static_cast<size_t>(i)].empty()) continue;
    out << ',';
    put(out, sim.states()[i]);
  }
  const auto& output_names = sim.output_names();
  for (int i = 0; i < sim.outputs().size(); ++i) {
    if (output_names[static_cast<size_t>(i)].empty()) continue;
    out << ',';
    put(out, sim.outputs()[i]);
  }
  for (double v :
       {sim.kinetic_energy(), sim.potential_energy(), sim.work(), sim.drift(), sim.phi_norm()}) {
    out << ',';
    put(out, v);
  }
  out << ',' << sim.last_step().iterations << '\n';
}

RunSummary run(Simulation& sim, std::ostream* csv, const std::function<void(double)>& progress) {
  RunSummary summary;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    sim.start();
    if (csv != nullptr) {
      write_csv_header(*csv, sim);
      write_csv_row(*csv, sim);
    }
    const double dt = sim.settings().dt;
    const double t_end = sim.settings().t_end;
    const long total = std::lround(t_end / dt);
    const long report_every = std::max(1L, total / 100);
    for (long k = 0; k < total; ++k) {
      sim.step();
      ++summary.steps;
      const int it = sim.last_step().iterations;
      summary.iterations += it;
      summary.max_iterations = std::max(summary.max_iterations, it);
      summary.max_abs_drift = std::max(summary.max_abs_drift, std::abs(sim.drift()));
      summary.max_phi_norm = std::max(summary.max_phi_norm, sim.phi_norm());
      if (csv != nullptr) write_csv_row(*csv, sim);
      if (progress && (k + 1) % report_every == 0)
        progress(static_cast<double>(k + 1) / static_cast<double>(total));
    }
  } catch (const SimulationError& err) {
    summary.failed = true;
    summary.failure = err.what();
  }
  if (csv != nullptr) csv->flush();
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace mh
