// One run for a profile (bench/performance.py runs it under valgrind
// --tool=callgrind): a shipped model, or a generated chain or tree, for a
// given simulated time, writing its CSV to /dev/null every step, every 10 ms
// or not at all.
//   mh_profile MODEL.yaml|chain:N|tree:N FORMULATION T_END [none|every-step|10ms]
//              [auto|per-step|full|modified|articulated] [klu|umfpack|dense|auto] [sens:K]
// sens:K carries forward sensitivities (sensitivities.hpp) for K parameters:
// the bodies' masses in order (each moving its inertia in proportion), then
// gravity's components. filter:ekf (or filter:ukf) runs the model as that
// Kalman filter instead (estimation: docs/estimation.md), every sensor of
// the model, then z1 and the first state, read every step; the readings
// are what the run itself gives before each update (zero innovations: the
// same work as any others), so that the step's cost is the filter's alone.
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/extended_kalman_filter.hpp"
#include "monohydra/core/filter_defaults.hpp"
#include "monohydra/core/unscented_kalman_filter.hpp"

namespace {

int run_filter(mh::Simulation& sim, const mh::ModelFile& file, const std::string& kind) {
  using namespace mh;
  if (kind != "ekf" && kind != "ukf") throw std::runtime_error("filter: expected ekf or ukf");
  sim.start();
  std::vector<FilterSensor> sensors;
  for (const SensorSpec& s : file.sensors) sensors.push_back(filter_sensor(s, "bench"));
  const std::vector<LinearVariable> states = state_variables(sim);
  sensors.push_back({"z1", "z1", 1e-4, 0.0});
  sensors.push_back({states.back().name, states.back().name, 1.0, 0.0});
  const FilterNoise noise = default_filter_noise(states, {});
  std::unique_ptr<StateFilter> f;
  if (kind == "ukf")
    f = std::make_unique<UnscentedKalmanFilter>(sim, sensors, noise,
                                                std::vector<ParameterDirection>{});
  else
    f = std::make_unique<ExtendedKalmanFilter>(sim, sensors, noise,
                                               std::vector<ParameterDirection>{});
  const CsvLayout layout(sim);
  std::vector<std::size_t> columns;
  for (const FilterSensor& s : sensors)
    for (std::size_t c = 0; c < layout.names().size(); ++c)
      if (layout.names()[c] == s.measures) columns.push_back(c);
  if (columns.size() != sensors.size())
    throw std::runtime_error("filter: a sensor's quantity is not a column of the run");
  std::vector<double> row(layout.names().size());
  Eigen::VectorXd readings(static_cast<Eigen::Index>(sensors.size()));
  long steps = 0;
  while (sim.time() < sim.settings().t_end - 0.5 * sim.settings().dt) {
    f->predict();
    layout.values(sim, row.data());
    for (std::size_t i = 0; i < columns.size(); ++i)
      readings[static_cast<Eigen::Index>(i)] = row[columns[i]];
    f->update(readings);
    ++steps;
  }
  std::cout << steps << " steps of the " << kind << " with " << sensors.size() << " sensors\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mh;
  std::size_t sensitivities = 0;
  std::string filter;
  if (argc >= 5 && std::string(argv[argc - 1]).rfind("sens:", 0) == 0) {
    sensitivities = std::stoul(std::string(argv[argc - 1]).substr(5));
    --argc;
  } else if (argc >= 5 && std::string(argv[argc - 1]).rfind("filter:", 0) == 0) {
    filter = std::string(argv[argc - 1]).substr(7);
    --argc;
  }
  if (argc < 4 || argc > 7) {
    std::cerr << "usage: mh_profile MODEL.yaml|chain:N|tree:N FORMULATION T_END "
                 "[none|every-step|10ms] [auto|per-step|full|modified|articulated] "
                 "[klu|umfpack|dense|auto] [sens:K|filter:ekf|filter:ukf]\n";
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
    std::vector<ParameterDirection> params;
    for (std::size_t j = 0; j < file.model.bodies.size() && params.size() < sensitivities; ++j) {
      const Body& b = file.model.bodies[j];
      ParameterDirection p;
      p.path = "bodies/" + b.name + "/mass";
      p.value = b.mass;
      p.bodies.push_back({static_cast<int>(j), 1.0, Eigen::Vector3d::Zero(), b.inertia_B / b.mass});
      params.push_back(p);
    }
    for (int i = 0; i < 3 && params.size() < sensitivities; ++i) {
      ParameterDirection p;
      p.path = "gravity/" + std::to_string(i);
      p.value = file.model.gravity[i];
      p.gravity[i] = 1.0;
      params.push_back(p);
    }
    if (params.size() < sensitivities)
      throw std::runtime_error("sens:K: the model has " + std::to_string(params.size()) +
                               " parameters of that kind");
    if (!params.empty()) sim.track_sensitivities(params);
    if (!filter.empty()) return run_filter(sim, file, filter);
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
