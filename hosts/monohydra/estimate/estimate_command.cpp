// monohydra estimate MODEL --measurements DATA.csv: the model run as a
// filter on a machine's recorded sensors (docs/estimation.md). Everything
// is checked before the first step; rows are written as the filter goes, so
// that a filter that stops keeps every row before it.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "estimate_report.hpp"
#include "measured_data.hpp"
#include "measurement_stream.hpp"
#include "model_settings.hpp"
#include "monohydra/core/csv_layout.hpp"
#include "monohydra/core/extended_kalman_filter.hpp"
#include "monohydra/core/filter_defaults.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/state_vector.hpp"
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
                 "CSV: t, then the sensors' names; an empty field is a sample not taken. '-': "
                 "lines t,NAME=VALUE,... from standard input, each estimate written as its line "
                 "arrives");
  app.add_option("--filter", filter_name,
                 "ekf (default: the extended Kalman filter on the step's own map) or ukf (the "
                 "unscented filter: no derivative, 2n sigma points a step); with --report a "
                 "list, ekf,ukf: each runs on the same data, the CSV is the first's");
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
  std::string report_dir, truth_path;
  app.add_option("--report", report_dir,
                 "write DIR/report.html: each filter's estimates with their 2-sigma bands beside "
                 "the model run open loop, the sensors against what each filter expected, and "
                 "with --truth each state's error");
  app.add_option("--truth", truth_path,
                 "with --report: a CSV of the machine's own run (t, then columns named as the "
                 "filter's states, as `run` writes them): each state's RMS error, the steps "
                 "inside its 2-sigma band, and the normalised estimation error squared");
  bool real_time = false;
  app.add_flag("--real-time", real_time,
               "pace the steps to the wall clock (from the first line's time on) and count the "
               "steps whose estimate came after the next step's time");
  StepOverrideOptions overrides(app, false, false);
  overrides.add_settings(app);
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!overrides.read(request.overrides)) return 2;
  if (models.size() != 1 || data_path.empty()) {
    std::cerr << "monohydra: estimate needs one model file and --measurements DATA.csv\n";
    return 2;
  }
  const std::vector<std::string> filters = split_list(filter_name);
  for (const std::string& f : filters)
    if (f != "ekf" && f != "ukf") {
      std::cerr << "monohydra: --filter " << f << ": expected ekf or ukf\n";
      return 2;
    }
  if (filters.empty() || (filters.size() > 1 && report_dir.empty())) {
    std::cerr << "monohydra: --filter " << filter_name
              << ": one filter, or a list of them with --report\n";
    return 2;
  }
  if (!truth_path.empty() && report_dir.empty()) {
    std::cerr << "monohydra: --truth is what --report compares the estimates with: give --report "
                 "DIR\n";
    return 2;
  }
  if (!report_dir.empty() && (data_path == "-" || real_time)) {
    std::cerr << "monohydra: --report takes the data of a file, not a stream or --real-time\n";
    return 2;
  }
  request.model_path = models.front();

  // Everything checked before the first step.
  const bool streamed = data_path == "-";
  MeasuredData data;
  if (!streamed) {
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
  }
  const auto prepared = prepare_run(request);
  if (!prepared) return 2;
  const double dt = prepared->sim->settings().dt;
  // The filter's sensors: the data's columns, or every sensor of the model
  // for a stream (whose lines may name any of them).
  std::vector<FilterSensor> sensors;
  const auto take_sensor = [&](const SensorSpec& found) {
    try {
      sensors.push_back(filter_sensor(found, request.model_path));
    } catch (const std::invalid_argument& err) {
      std::cerr << "monohydra: " << err.what() << '\n';
      return false;
    }
    return true;
  };
  if (streamed) {
    if (prepared->file.sensors.empty()) {
      std::cerr << "monohydra: " << request.model_path
                << ": the model has no sensors: add a sensors: list\n";
      return 2;
    }
    for (const SensorSpec& s : prepared->file.sensors)
      if (!take_sensor(s)) return 2;
  }
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
    if (!take_sensor(*found)) return 2;
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

  // The report's readings (and the truth), a row per step.
  EstimateReport report;
  MeasuredData truth;
  if (!report_dir.empty()) {
    report.model = request.model_path;
    report.data_path = data_path;
    report.measured = Eigen::MatrixXd::Constant(prepared->steps + 1,
                                                static_cast<Eigen::Index>(sensors.size()), NAN);
    for (const auto& [k, row] : row_at_step)
      if (k <= prepared->steps)
        for (size_t c = 0; c < sensors.size(); ++c)
          report.measured(k, static_cast<Eigen::Index>(c)) = data.values[c][row];
    for (const FilterSensor& f : sensors) report.sensors.push_back(f.name);
    if (!truth_path.empty()) {
      try {
        truth = read_measured_data(truth_path);
      } catch (const std::exception& err) {
        std::cerr << "monohydra: --truth: " << err.what() << '\n';
        return 2;
      }
    }
  }
  std::ofstream file;
  std::ostream discard(nullptr);  // a second filter's rows: the CSV is the first's

  // One filter over the data: `sim` started, the filter set up (its noise
  // levels checked) before the CSV is opened; its rows written when `csv`,
  // each step recorded in `track` for the report. 0, 1 (stopped, the rows
  // before kept) or 2 (refused before the first step).
  const auto run_filter = [&](const std::string& name, Simulation& sim, bool csv,
                              FilterTrack* track) -> int {
    const std::clock_t cpu0 = std::clock();
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
      const FilterNoise defaults = default_filter_noise(states, params);
      Eigen::VectorXd plant(n + k), initial(n + k);
      plant << defaults.plant, defaults.parameter_plant;
      initial << defaults.initial, defaults.parameter_initial;
      for (const ParameterDirection& p : params) states.push_back({p.path, ""});
      if (!apply_noise(plant_texts, "--plant-noise", states, plant) ||
          !apply_noise(initial_texts, "--initial-sd", states, initial))
        return 2;
      const FilterNoise noise{plant.head(n), initial.head(n), plant.tail(k), initial.tail(k)};
      if (name == "ukf")
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
    if (track != nullptr) {
      if (report.states.empty()) {
        for (const LinearVariable& v : states) {
          report.states.push_back(v.name);
          report.units.push_back(v.unit);
        }
        if (!truth_path.empty()) {
          try {
            attach_truth(report, truth, dt);
          } catch (const std::invalid_argument& err) {
            std::cerr << "monohydra: --truth: " << err.what() << '\n';
            return 2;
          }
        }
      }
      track->label = name;
      track->estimate = track->sd = Eigen::MatrixXd::Constant(report.measured.rows(), n, NAN);
      track->predicted =
          Eigen::MatrixXd::Constant(report.measured.rows(), report.measured.cols(), NAN);
    }
    if (csv && !out_path.empty()) {
      file.open(out_path);
      if (!file) {
        std::cerr << "monohydra: cannot write '" << out_path << "'\n";
        return 2;
      }
    }
    std::ostream& out = !csv ? discard : out_path.empty() ? std::cout : file;
    using Clock = std::chrono::steady_clock;
    Clock::time_point wall0{};  // --real-time: the wall time of t = 0
    const auto due = [&](long step) {
      return wall0 + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(static_cast<double>(step) * dt));
    };
    long paced = 0, missed = 0, late = 0;
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
      const Eigen::VectorXd none =
          Eigen::VectorXd::Constant(static_cast<Eigen::Index>(sensors.size()), NAN);
      long k = 0;                             // the filter's step
      bool updated = false, written = false;  // at step k
      bool paced_now = false;                 // --real-time, once its clock is set
      const auto write_row = [&] {
        layout.values(sim, row.data());
        for (size_t c = 0; c < row.size(); ++c) out << (c == 0 ? "" : ",") << number(row[c]);
        const Eigen::VectorXd estimate = filter.state();
        for (Eigen::Index i = x_count; i < n; ++i) out << ',' << number(estimate[i]);
        for (Eigen::Index i = 0; i < n; ++i)
          out << ',' << number(std::sqrt(filter.covariance()(i, i)));
        for (Eigen::Index c = 0; c < none.size(); ++c)
          out << ',' << number(filter.innovation()[c]) << ',' << number(filter.innovation_sd()[c]);
        out << ',' << number(filter.samples() > 0 ? filter.nis() : NAN) << ',' << filter.samples()
            << '\n';
        if (streamed) out.flush();
        written = true;
        if (track != nullptr && k < report.measured.rows()) {
          track->t.push_back(static_cast<double>(k) * dt);
          track->estimate.row(k) = estimate.transpose();
          for (Eigen::Index i = 0; i < n; ++i)
            track->sd(k, i) = std::sqrt(filter.covariance()(i, i));
          for (Eigen::Index c = 0; c < none.size(); ++c)
            track->predicted(k, c) = report.measured(k, c) - filter.innovation()[c];
          track->nees.push_back(nees_at(report, k, estimate, filter.covariance()));
        }
        // A step's estimate is due before the next step's time.
        if (paced_now) {
          ++paced;
          if (Clock::now() > due(k + 1)) ++missed;
        }
      };
      // Step k finished (its update, its row), then the step to k + 1.
      const auto leave_step = [&] {
        if (!updated) filter.update(none);
        if (!written) write_row();
        if (paced_now) std::this_thread::sleep_until(due(k + 1));
        filter.predict();
        ++k;
        updated = written = false;
      };
      const auto take = [&](const Eigen::VectorXd& readings, bool row_now) {
        filter.update(readings);
        updated = true;
        if (row_now) write_row();
      };
      const long last_step = streamed && !request.overrides.t_end ? -1 : prepared->steps;
      if (!streamed) {
        if (real_time) {
          wall0 = Clock::now();
          paced_now = true;
        }
        Eigen::VectorXd readings(none.size());
        for (long target = 0; target <= last_step; ++target) {
          while (k < target) leave_step();
          const auto at = row_at_step.find(target);
          if (at == row_at_step.end()) continue;
          for (size_t c = 0; c < sensors.size(); ++c)
            readings[static_cast<Eigen::Index>(c)] = data.values[c][at->second];
          take(readings, !real_time);
        }
      } else {
        std::vector<std::string> names(sensors.size());
        for (size_t c = 0; c < sensors.size(); ++c) names[c] = sensors[c].name;
        MeasurementStream stream(std::cin, names, "standard input");
        MeasurementLine line;
        // A line's step; -1 past --t-end (the end).
        const auto step_of = [&](const MeasurementLine& l) {
          const long target = std::lround(l.t / dt);
          if (target < 0)
            throw InputError({"standard input", static_cast<int>(l.number), 0}, "t",
                             "a time at or after the run's start (0 s), not " + number(l.t));
          return last_step >= 0 && target > last_step ? -1L : target;
        };
        if (!real_time) {
          // Each line as it comes: the steps up to it predicted, its update,
          // its row at once.
          while (stream.next(line)) {
            const long target = step_of(line);
            if (target < 0) break;
            if (target < k || (target == k && updated))
              throw InputError({"standard input", static_cast<int>(line.number), 0}, "t",
                               "one line per step of " + number(dt) + " s: t = " + number(line.t) +
                                   " falls on the step of the line before");
            while (k < target) leave_step();
            take(line.readings, true);
          }
        } else {
          // The steps paced by the wall clock from the first line on; lines
          // read by a thread of their own and taken at the step they fall on,
          // or at once when they come after it (counted late).
          MeasurementQueue queue(stream, 0);  // standard input
          if (queue.pop_wait(line) && step_of(line) >= 0) {
            const long first = step_of(line);
            wall0 = Clock::now() - std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(line.t));
            bool have = true;
            while (k < first) leave_step();
            paced_now = true;
            for (;;) {
              while (have) {
                const long target = step_of(line);
                if (target < 0 || target > k) break;
                if (target < k) ++late;
                take(line.readings, false);
                have = queue.pop(line);
              }
              if (have && step_of(line) < 0) break;
              if (!have && queue.ended()) break;
              if (last_step >= 0 && k >= last_step) break;
              leave_step();
              if (!have) have = queue.pop(line);
            }
          }
          queue.rethrow();
        }
      }
      if (!updated) filter.update(none);
      if (!written) write_row();
    } catch (const std::exception& err) {
      out.flush();
      std::cerr << "monohydra: " << err.what() << " (the rows before it are written)\n";
      return 1;
    }
    if (real_time) {
      char percent[32];
      std::snprintf(
          percent, sizeof(percent), "%.2f",
          paced > 0 ? 100.0 * static_cast<double>(missed) / static_cast<double>(paced) : 0.0);
      std::cerr << "real time: deadlines missed: " << missed << " of " << paced << " steps ("
                << percent << " %)";
      if (streamed) std::cerr << ", lines taken after their step: " << late;
      std::cerr << "; these results depend on this machine's speed and load\n";
    }
    out.flush();
    if (out.rdbuf() != nullptr && !out) {  // (a second filter's rows are discarded)
      std::cerr << "monohydra: writing the estimates failed\n";
      return 1;
    }
    if (track != nullptr)
      track->cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    return 0;
  };

  if (report_dir.empty()) return run_filter(filters.front(), *prepared->sim, true, nullptr);
  // The open loop: the model alone from the same start.
  {
    const std::clock_t cpu0 = std::clock();
    const auto open = prepare_run(request);
    if (!open) return 2;
    FilterTrack track;
    track.label = "open loop";
    try {
      open->sim->start();
      for (long k = 0; k <= prepared->steps; ++k) {
        if (k > 0) open->sim->step();
        const Eigen::VectorXd x = state_values(*open->sim);
        if (k == 0) track.estimate = Eigen::MatrixXd::Constant(prepared->steps + 1, x.size(), NAN);
        track.t.push_back(static_cast<double>(k) * dt);
        track.estimate.row(k) = x.transpose();
      }
    } catch (const std::exception& err) {
      std::cerr << "monohydra: the open loop: " << err.what() << '\n';
      return 1;
    }
    track.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    report.filters.push_back(std::move(track));
  }
  for (size_t f = 0; f < filters.size(); ++f) {
    const auto again = f == 0 ? nullptr : prepare_run(request);
    if (f > 0 && !again) return 2;
    FilterTrack track;
    const int code = run_filter(filters[f], f == 0 ? *prepared->sim : *again->sim, f == 0, &track);
    if (code != 0) return code;
    report.filters.push_back(std::move(track));
  }
  try {
    std::filesystem::create_directories(report_dir);
    std::ofstream html(std::filesystem::path(report_dir) / "report.html");
    html << estimate_report_html(report);
    if (!html) throw std::runtime_error("cannot write " + report_dir + "/report.html");
  } catch (const std::exception& err) {
    std::cerr << "monohydra: --report: " << err.what() << '\n';
    return 1;
  }
  std::cerr << "wrote " << report_dir << "/report.html\n";
  return 0;
}

}  // namespace mh::cli
