// monohydra estimate MODEL --measurements DATA.csv: the model run as a
// filter on a machine's recorded sensors (docs/estimation.md). Everything
// is checked before the first step; rows are written as the filter goes, so
// that a filter that stops keeps every row before it.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "measured_data.hpp"
#include "model_settings.hpp"
#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/extended_kalman_filter.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/unscented_kalman_filter.hpp"
#include "run_setup.hpp"
#include "sensitivity_columns.hpp"
#include "step_overrides.hpp"
#include "subcommand_parser.hpp"

namespace mh::cli {

namespace {

std::string number(double v) {
  if (std::isnan(v)) return "";
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", v);
  return text;
}

// The default noise of a state, by its unit (docs/estimation.md: the
// four-bar's tuning): plant noise on rates and pressures, none on positions.
double default_plant(const std::string& unit) {
  if (unit == "Pa") return 1e4;
  if (unit.size() > 2 && unit.substr(unit.size() - 2) == "/s") return 3e-2;
  if (unit == "rad" || unit == "m") return 0.0;
  return 1e-3;
}
double default_initial(const std::string& unit) {
  return unit == "Pa" ? 1e5 : 1e-3;
}

// STATE=SD settings onto `values`, by the states' names; false after saying why.
bool apply_noise(const std::vector<std::string>& texts, const char* option,
                 const std::vector<LinearVariable>& states, Eigen::VectorXd& values) {
  for (const std::string& text : texts) {
    const host::PathSetting s = host::parse_setting(text);
    size_t i = 0;
    while (i < states.size() && states[i].name != s.path) ++i;
    if (i == states.size()) {
      std::string known;
      for (const LinearVariable& v : states) known += (known.empty() ? "" : ", ") + v.name;
      std::cerr << "monohydra: " << option << " " << text << ": '" << s.path
                << "' is not a state of the filter (its states: " << known << ")\n";
      return false;
    }
    const std::optional<double> sd = parse_number(std::string(option) + " " + s.path, s.value);
    if (!sd) return false;
    if (!(*sd >= 0.0) || !std::isfinite(*sd)) {
      std::cerr << "monohydra: " << option << " " << text
                << ": expected a standard deviation of 0 or more\n";
      return false;
    }
    values[static_cast<Eigen::Index>(i)] = *sd;
  }
  return true;
}

}  // namespace

int estimate(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "estimate",
      "Run MODEL.yaml as an extended Kalman filter on the readings of its sensors: in "
      "--measurements DATA.csv (t, then columns named as the model's sensors: an empty field "
      "is no sample): every column `run` writes, estimated, then each state's standard "
      "deviation NAME_sd, each sensor's innovation and its standard deviation, and the "
      "normalised innovation squared (nis) with the samples it had.");
  CLI::App& app = *app_holder;
  std::vector<std::string> models, plant_texts, initial_texts;
  std::string data_path, filter_name = "ekf", out_path, params_text;
  RunRequest request;
  app.add_option("MODEL.yaml", models, "the model file, with its sensors:");
  app.add_option("--measurements", data_path,
                 "CSV: t, then the sensors' names; an empty field is a sample not taken");
  app.add_option("--filter", filter_name,
                 "ekf (default: the extended Kalman filter on the step's own map) or ukf (the "
                 "unscented filter: no derivative, 2n sigma points a step)");
  app.add_option("--plant-noise", plant_texts,
                 "STATE=SD: the standard deviation the state's error gains in a second (its "
                 "unit per sqrt(s)); defaults by unit: 1e4 Pa, 3e-2 for a rate, 0 for a "
                 "position, 1e-3 else");
  app.add_option("--initial-sd", initial_texts,
                 "STATE=SD: the initial state's error (default 1e5 Pa, 1e-3 else)");
  app.add_option("--estimate-params", params_text,
                 "estimate these parameters beside the state (paths as --set names them, "
                 "comma-separated): each a column of its own and PATH_sd; its --plant-noise "
                 "(default 0: a constant) and --initial-sd (default a fifth of its value) by "
                 "its path");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  app.add_option("--out", out_path, "write the CSV to FILE instead of stdout");
  StepOverrideOptions overrides(app, false, false);
  overrides.add_settings(app);
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!overrides.read(request.overrides)) return 2;
  if (models.size() != 1 || data_path.empty()) {
    std::cerr << "monohydra: estimate needs one model file and --measurements DATA.csv\n";
    return 2;
  }
  if (filter_name != "ekf" && filter_name != "ukf") {
    std::cerr << "monohydra: --filter " << filter_name << ": expected ekf or ukf\n";
    return 2;
  }
  request.model_path = models.front();

  // Everything checked before the first step.
  MeasuredData data;
  try {
    data = read_measured_data(data_path);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  // Without --t-end, the run ends at the last sample.
  if (!request.overrides.t_end) {
    if (!(data.t.back() > 0.0)) {
      std::cerr << "monohydra: " << data_path
                << ": its last sample is at the start: the filter runs to the last sample "
                   "(or to --t-end)\n";
      return 2;
    }
    request.overrides.t_end = data.t.back();
  }
  const auto prepared = prepare_run(request);
  if (!prepared) return 2;
  Simulation& sim = *prepared->sim;
  const double dt = sim.settings().dt;
  std::vector<FilterSensor> sensors;
  for (const std::string& column : data.names) {
    const SensorSpec* found = nullptr;
    for (const SensorSpec& s : prepared->file.sensors)
      if (s.name == column) found = &s;
    if (found == nullptr) {
      std::string known;
      for (const SensorSpec& s : prepared->file.sensors)
        known += (known.empty() ? "" : ", ") + s.name;
      std::cerr << "monohydra: " << data_path << ": column '" << column
                << "' is not one of the model's sensors ("
                << (known.empty() ? "it has none: add a sensors: list" : known) << ")\n";
      return 2;
    }
    if (found->delay != 0.0) {
      std::cerr << "monohydra: sensor '" << found->name << "' (" << request.model_path
                << "): a delay of " << found->delay
                << " s: the filter takes each reading at its own time (delays are not yet "
                   "estimated)\n";
      return 2;
    }
    if (!(found->noise > 0.0)) {
      std::cerr << "monohydra: sensor '" << found->name << "' (" << request.model_path
                << "): a filter needs its noise (a standard deviation above 0)\n";
      return 2;
    }
    sensors.push_back({found->name, found->measures, found->noise, found->bias});
  }
  // Each row at the step nearest its time; two rows on one step refused.
  std::map<long, size_t> row_at_step;
  for (size_t i = 0; i < data.t.size(); ++i) {
    const long k = std::lround(data.t[i] / dt);
    if (k < 0) {
      std::cerr << "monohydra: " << data_path << ": t = " << data.t[i]
                << " is before the run's start\n";
      return 2;
    }
    if (!row_at_step.emplace(k, i).second) {
      std::cerr << "monohydra: " << data_path << ": the rows at t = " << data.t[row_at_step[k]]
                << " and t = " << data.t[i] << " fall on the same step of " << dt
                << " s: one row per step\n";
      return 2;
    }
  }

  // The filter set up (its noise levels checked) before the file is opened.
  std::unique_ptr<StateFilter> made;
  try {
    sim.start();
    std::vector<LinearVariable> states = state_variables(sim);
    const auto n = static_cast<Eigen::Index>(states.size());
    const std::vector<std::string> paths = split_list(params_text);
    std::vector<ParameterDirection> params;
    try {
      params = parameter_directions(request, prepared->file, paths);
    } catch (const std::invalid_argument& err) {
      std::cerr << "monohydra: --estimate-params: " << err.what() << '\n';
      return 2;
    }
    const auto k = static_cast<Eigen::Index>(params.size());
    Eigen::VectorXd plant(n + k), initial(n + k);
    for (Eigen::Index i = 0; i < n; ++i) {
      plant[i] = default_plant(states[static_cast<size_t>(i)].unit);
      initial[i] = default_initial(states[static_cast<size_t>(i)].unit);
    }
    for (Eigen::Index j = 0; j < k; ++j) {
      const double v = params[static_cast<size_t>(j)].value;
      plant[n + j] = 0.0;
      initial[n + j] = 0.2 * (v != 0.0 ? std::abs(v) : 1.0);
      states.push_back({params[static_cast<size_t>(j)].path, ""});
    }
    if (!apply_noise(plant_texts, "--plant-noise", states, plant) ||
        !apply_noise(initial_texts, "--initial-sd", states, initial))
      return 2;
    const FilterNoise noise{plant.head(n), initial.head(n), plant.tail(k), initial.tail(k)};
    if (filter_name == "ukf")
      made = std::make_unique<UnscentedKalmanFilter>(sim, sensors, noise, params);
    else
      made = std::make_unique<ExtendedKalmanFilter>(sim, sensors, noise, params);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  StateFilter& filter = *made;
  const std::vector<LinearVariable>& states = filter.states();
  const auto n = static_cast<Eigen::Index>(states.size());
  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) {
      std::cerr << "monohydra: cannot write '" << out_path << "'\n";
      return 2;
    }
  }
  std::ostream& out = out_path.empty() ? std::cout : file;
  try {
    const CsvLayout layout(sim);
    std::vector<double> row(layout.names().size());
    const Eigen::Index x_count = filter.num_x();
    out << "t";
    for (size_t c = 1; c < layout.names().size(); ++c) out << ',' << layout.names()[c];
    for (Eigen::Index i = x_count; i < n; ++i) out << ',' << states[static_cast<size_t>(i)].name;
    for (const LinearVariable& v : states) out << ',' << v.name << "_sd";
    for (const FilterSensor& s : sensors)
      out << ',' << s.name << "_innovation," << s.name << "_innovation_sd";
    out << ",nis,samples\n";
    Eigen::VectorXd readings(static_cast<Eigen::Index>(sensors.size()));
    for (long k = 0; k <= prepared->steps; ++k) {
      if (k > 0) filter.predict();
      const auto at = row_at_step.find(k);
      for (size_t c = 0; c < sensors.size(); ++c)
        readings[static_cast<Eigen::Index>(c)] =
            at == row_at_step.end() ? NAN : data.values[c][at->second];
      filter.update(readings);
      layout.values(sim, row.data());
      for (size_t c = 0; c < row.size(); ++c) out << (c == 0 ? "" : ",") << number(row[c]);
      const Eigen::VectorXd estimate = filter.state();
      for (Eigen::Index i = x_count; i < n; ++i) out << ',' << number(estimate[i]);
      for (Eigen::Index i = 0; i < n; ++i)
        out << ',' << number(std::sqrt(filter.covariance()(i, i)));
      for (Eigen::Index c = 0; c < readings.size(); ++c)
        out << ',' << number(filter.innovation()[c]) << ',' << number(filter.innovation_sd()[c]);
      out << ',' << number(filter.samples() > 0 ? filter.nis() : NAN) << ',' << filter.samples()
          << '\n';
    }
  } catch (const std::exception& err) {
    out.flush();
    std::cerr << "monohydra: " << err.what() << " (the rows before it are written)\n";
    return 1;
  }
  out.flush();
  if (!out) {
    std::cerr << "monohydra: writing the estimates failed\n";
    return 1;
  }
  return 0;
}

}  // namespace mh::cli
