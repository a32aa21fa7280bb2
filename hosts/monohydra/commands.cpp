#include "commands.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "call_watchdog.hpp"
#include "checkpoint.hpp"
#include "cli_support.hpp"
#include "compare.hpp"
#include "crash_report.hpp"
#include "input_feed.hpp"
#include "model_plugins.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/sensor_sampler.hpp"
#include "monohydra/core/simulation.hpp"
#include "monohydra/cpp/number_text.hpp"
#include "result_sidecar.hpp"
#include "run_setup.hpp"
#include "stability_text.hpp"
#include "step_overrides.hpp"
#include "stop_signals.hpp"
#include "subcommand_parser.hpp"
#include "supervised.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

const char* kUsage =
    "usage: monohydra [COMMAND] [ARGS]\n"
    "  (no command)            the paper's comparison: its case studies (models/paper-\n"
    "                          reference.yaml), the paper's numbers beside ours; reports in out/\n"
    "  plugins [--model MODEL.yaml]\n"
    "                          list every plugin found (with the model's plugin_paths and\n"
    "                          plugins: choices), its components and ABI version, and every\n"
    "                          id that two libraries offer\n"
    "  run MODEL.yaml [--formulation NAME] [--integrator NAME] [--dt S] [--t-end S]\n"
    "                 [--set PATH=VALUE]... [--sensors-out FILE.csv [--seed N]]\n"
    "                 [--out FILE.csv | --stream] [--output-interval S]\n"
    "                 [--real-time [--newton-cap N]] [--inputs FILE.csv|-]\n"
    "                 [--save-state FILE [--at T]] [--resume FILE] [LIMITS]\n"
    "                          simulate MODEL.yaml; CSV columns: t, z1..zN, states,\n"
    "                          outputs, KE, PE, W, drift, phi_norm, iters (the model's\n"
    "                          output: selects them); --output-interval S writes rows at\n"
    "                          multiples of S only; --real-time paces the steps to the wall\n"
    "                          clock, each due at its simulated time, Newton stopping at N\n"
    "                          iterations (default 4) or the deadline, and adds the CSV\n"
    "                          columns late (s) and unconverged (|dx|/tol); --inputs sets\n"
    "                          the model's inputs from t,NAME,... rows or from name=value\n"
    "                          lines on stdin (-); --stream writes the rows to stdout;\n"
    "                          --save-state writes a checkpoint that --resume goes on from;\n"
    "                          --set PATH=VALUE sets a value of the model by its path\n"
    "                          (bodies/boom/mass=250; run, validate and compare)\n"
    "                          --sensors-out FILE.csv [--seed N] writes what the model's\n"
    "                          sensors: read (docs/model-format.md)\n"
    "  run MODEL.yaml --report DIR [--formulation NAME] [--integrator NAME]\n"
    "                 [--dt S] [--t-end S] [LIMITS]\n"
    "                          the run's report: DIR/report.html (the animated 3D view and\n"
    "                          the figures, as compare --report) and its CSV in DIR\n"
    "  compare MODEL.yaml [--formulations A,B,...] [--integrators C,D,...] [--report DIR]\n"
    "                     [--dt S] [--t-end S] [LIMITS]\n"
    "                          run every formulation with every integrator on MODEL.yaml\n"
    "                          (default: the model file's compare: lists, else its own\n"
    "                          choice) and print their numbers side by side; --report\n"
    "                          writes DIR/report.html with the paper's figures and each\n"
    "                          run's CSV, named after what varies\n"
    "  validate MODEL.yaml [--formulation NAME] [--integrator NAME] [--dt S] [--t-end S]\n"
    "                      [--output-interval S] [--real-time [--newton-cap N]] [LIMITS]\n"
    "                          load MODEL.yaml and set the run up without stepping: OK or the\n"
    "                          error (exit 0 or 1)\n"
    "  sweep STUDY.yaml --out DIR [--jobs N] [--dt S] [--t-end S] [--report] [--keep-csv]\n"
    "                          run every case of a study (docs/sweeps.md) on all cores, or on\n"
    "                          every rank under mpirun; one row per case in DIR/results.csv;\n"
    "                          started again with the same DIR, runs only the cases left\n"
    "  check PLUGIN.so [MODEL.yaml]\n"
    "                          load one plugin library and drive each of its components\n"
    "                          through its contract on MODEL.yaml (default: the shipped four-\n"
    "                          bar, or the smallest shipped model using a subsystem): load and\n"
    "                          version, descriptors, create/destroy cycles, bad options refused,\n"
    "                          analytic tangent against differences, bit-identical reruns,\n"
    "                          snapshots restored; each in a child process (exit 0 or 1)\n"
    "  linearize MODEL.yaml [--at T] [--outputs NAME,...] [--formulation NAME]\n"
    "                       [--integrator NAME] [--out FILE]\n"
    "                          run to T (default 0) and write A, B, C, D of the model about\n"
    "                          that state (its inputs, the outputs named) and the eigenvalues\n"
    "                          of A as YAML (docs/cli.md)\n"
    "  forces MODEL.yaml --bucket-cylinder NAME --arm-cylinder NAME [--lip BODY:X,Y,Z]\n"
    "                    [--pressure PA]\n"
    "                          an excavator's rated tool forces of ISO 6015 at the bucket lip:\n"
    "                          the bucket and the arm cylinder's at their relief pressure, the\n"
    "                          largest over each stroke with its pose (docs/soil.md)\n"
    "  sensitivities MODEL.yaml --params PATH,... [--formulation NAME] [--integrator NAME]\n"
    "                       [--dt S] [--t-end S] [--set PATH=VALUE] [--out FILE.csv]\n"
    "                          run as `run` does and write d(NAME)/d(PATH) of every coordinate,\n"
    "                          named state and output, one row per step (docs/identification.md)\n"
    "  fit MODEL.yaml --data MEASURED.csv --params PATH,... [--noise COLUMN=SIGMA]...\n"
    "               [--out DIR] [--max-iterations N] [run's --formulation --integrator --dt\n"
    "               --t-end --set]\n"
    "                          the parameters' values that best match the measured columns,\n"
    "                          with standard errors, 95 % intervals and identifiability; --out\n"
    "                          writes estimates.csv, fitted.yaml, report.html\n"
    "                          (docs/identification.md)\n"
    "  estimate MODEL.yaml --measurements DATA.csv [--filter ekf|ukf]\n"
    "                    [--estimate-params PATH,...] [--plant-noise STATE=SD]...\n"
    "                    [--initial-sd STATE=SD]... [--out FILE.csv]\n"
    "                    [run's --formulation --integrator --dt --t-end --set]\n"
    "                          the model as a Kalman filter (extended or unscented) on its\n"
    "                          sensors' readings: every column `run` writes, estimated, with\n"
    "                          each state's standard deviation and the innovations; the\n"
    "                          parameters named estimated beside the state\n"
    "                          (docs/estimation.md)\n"
    "  fmu MODEL.yaml --out FILE.fmu [--fmi-version 3|2] [--formulation NAME]\n"
    "                 [--integrator NAME] [--model-identifier ID]\n"
    "                          write the model as a Co-Simulation FMU that runs without\n"
    "                          monohydra installed: CSV columns as outputs, inputs, numeric\n"
    "                          options as parameters, FMU states (docs/fmi.md)\n"
    "  COMMAND --help          that command's options\n"
    "  --explicit-stability error|warn|off (run, validate, compare): an explicit integrator's\n"
    "  step beyond its stability bound stops the run, is reported (default) or not checked\n"
    "  LIMITS: --max-steps N (default 1e8), --max-output-bytes N (default 1e10)\n"
    "SIGINT or SIGTERM stops a run after its current row (exit 130 or 143).\n"
    "--log-level error|warn|info|debug (any command): the plugins' and the host's log lines\n"
    "  shown on stderr, default warn.\n"
    "run and compare print which library each component came from and write NAME.meta.json\n"
    "beside every CSV: versions, libraries, the model's SHA-256, the command and settings.\n"
    "plugins are searched in the libraries of the model's plugins: map, its plugin_paths,\n"
    "$MONOHYDRA_PLUGIN_PATH, beside the executable, then the install prefix; an id that\n"
    "two libraries offer must be chosen in the model file: plugins: {ID: LIBRARY.so}.\n";

std::string version_text(const mh_version& v) {
  return std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch);
}

// Real-time mode's Newton iterations per step unless --newton-cap says: twice
// what the case studies need on average (about 2), so a cap binds only where
// a step is hard.
constexpr int kDefaultNewtonCap = 4;

// run's and validate's arguments (CLI11, with --help); an exit code when
// they are wrong or help was asked for.
std::optional<int> parse_run_args(const std::vector<std::string>& args, const char* command,
                                  RunRequest& request, std::string* out) {
  const auto app_holder = subcommand_app(
      command, out != nullptr
                   ? "Simulate MODEL.yaml from t = 0 to t_end; CSV columns t, z1..zN, states, "
                     "outputs, KE, PE, W, drift, phi_norm, iters (the model's output: selects "
                     "them), and NAME.meta.json beside the CSV."
                   : "Load MODEL.yaml and set the run up without stepping: OK or the error "
                     "(exit 0 or 1).");
  CLI::App& app = *app_holder;
  std::vector<std::string> models;
  std::string interval, cap, call_timeout;
  bool real_time = false;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  StepOverrideOptions overrides(app, true, true);
  overrides.add_settings(app);
  if (out != nullptr) app.add_option("--out", *out, "write the results to FILE.csv");
  auto* interval_opt =
      app.add_option("--output-interval", interval, "write rows at multiples of S (s) only");
  app.add_flag("--real-time", real_time,
               "pace the steps to the wall clock; adds the columns late and unconverged");
  auto* cap_opt =
      app.add_option("--newton-cap", cap, "real time: Newton iterations per step (default 4)");
  auto* timeout_opt = app.add_option(
      "--call-timeout", call_timeout,
      "stop when one plugin call has not returned within S s, naming it (default 30 for "
      "create, setup, start and destroy, 5 for a call inside a step; 0: never)");
  std::string save_at;
  CLI::Option* at_opt = nullptr;
  std::string sensors_out_path, seed_text;
  CLI::Option* seed_opt = nullptr;
  if (out != nullptr) {
    app.add_option("--save-state", request.save_state,
                   "write the whole run state to FILE at --at T (default: the end), for --resume");
    at_opt = app.add_option("--at", save_at, "with --save-state: the time (s) of the checkpoint");
    app.add_option("--resume", request.resume,
                   "go on from a --save-state FILE: rows from its time on, bit for bit");
    app.add_option("--inputs", request.inputs,
                   "set the model's inputs from FILE.csv (t,NAME,... rows), or '-': lines "
                   "name=value from standard input, each applied at the next step");
    app.add_flag("--stream", request.stream,
                 "write each row to standard output as it is computed (the summary to stderr)");
    app.add_option("--sensors-out", sensors_out_path,
                   "write what the model's sensors: read to FILE.csv (t and one column per "
                   "sensor, an empty field where it took no sample)");
    seed_opt = app.add_option("--seed", seed_text,
                              "with --sensors-out: the seed of the sensors' noise (default 1)");
    app.add_option("--report", request.report_dir,
                   "write DIR/report.html (the 3D view and the figures, as compare --report) "
                   "and the run's CSV in DIR");
  }
  if (const auto code = parse_subcommand(app, args)) return code;
  if (!overrides.read(request.overrides)) return 2;

  if (models.size() > 1) {
    std::cerr << "monohydra: one model file at a time (got '" << models[0] << "' and '" << models[1]
              << "')\n";
    return 2;
  }
  if (models.empty()) {
    std::cerr << "monohydra: " << command << " needs a model file\n";
    return usage(2);
  }
  request.model_path = models.front();
  request.call_limits = CallLimits{};
  if (timeout_opt->count() > 0) {
    const std::optional<double> value = parse_number("--call-timeout", call_timeout);
    if (!value) return 2;
    if (!std::isfinite(*value) || *value < 0.0) {
      std::cerr << "monohydra: --call-timeout expects a time in s (0 or more), got '"
                << call_timeout << "'\n";
      return 2;
    }
    request.call_limits = CallLimits::uniform(*value);
  }
  if (interval_opt->count() > 0) {
    request.output_interval = parse_number("--output-interval", interval);
    if (!request.output_interval) return 2;
    if (!std::isfinite(*request.output_interval) || !(*request.output_interval > 0.0)) {
      std::cerr << "monohydra: --output-interval expects a positive time (s), got '" << interval
                << "'\n";
      return 2;
    }
  }
  int newton_cap = 0;
  if (cap_opt->count() > 0) {
    const std::optional<double> value = parse_number("--newton-cap", cap);
    if (!value) return 2;
    if (!(*value >= 1.0 && *value <= 1000.0) || *value != std::floor(*value)) {
      std::cerr << "monohydra: --newton-cap expects an integer from 1 to 1000, got '" << cap
                << "'\n";
      return 2;
    }
    newton_cap = static_cast<int>(*value);
  }
  if (newton_cap > 0 && !real_time) {
    std::cerr << "monohydra: --newton-cap applies to --real-time runs only\n";
    return 2;
  }
  if (real_time) request.real_time_cap = newton_cap > 0 ? newton_cap : kDefaultNewtonCap;
  if (at_opt != nullptr && at_opt->count() > 0) {
    if (request.save_state.empty()) {
      std::cerr << "monohydra: --at applies to --save-state only\n";
      return 2;
    }
    request.save_at = parse_number("--at", save_at);
    if (!request.save_at) return 2;
    if (!std::isfinite(*request.save_at) || !(*request.save_at > 0.0)) {
      std::cerr << "monohydra: --at expects a positive time (s), got '" << save_at << "'\n";
      return 2;
    }
  }
  request.sensors_out = sensors_out_path;
  if (seed_opt != nullptr && seed_opt->count() > 0) {
    if (request.sensors_out.empty()) {
      std::cerr << "monohydra: --seed applies to --sensors-out only\n";
      return 2;
    }
    const bool digits = !seed_text.empty() && seed_text.size() <= 19 &&
                        seed_text.find_first_not_of("0123456789") == std::string::npos;
    if (!digits) {
      std::cerr << "monohydra: --seed expects a whole number from 0 to 10^19 - 1, got '"
                << seed_text << "'\n";
      return 2;
    }
    request.seed = std::stoull(seed_text);
  }
  if (request.stream && out != nullptr && !out->empty()) {
    std::cerr << "monohydra: --stream writes the rows to standard output: give --out or "
                 "--stream, not both\n";
    return 2;
  }
  return std::nullopt;
}

// Real-time mode's account: deadlines missed and steps accepted unconverged,
// and that these results depend on the machine.
void print_real_time(std::ostream& out, const RunSummary& s, int cap) {
  const double steps = std::max(1.0, static_cast<double>(s.steps));
  out << "real time:    deadlines missed: " << s.deadlines_missed << " of " << s.steps << " steps ("
      << 100.0 * static_cast<double>(s.deadlines_missed) / steps << " %), worst "
      << 1e3 * s.max_late << " ms late, mean "
      << (s.deadlines_missed > 0 ? 1e3 * s.total_late / static_cast<double>(s.deadlines_missed)
                                 : 0.0)
      << " ms late\n"
      << "              accepted unconverged: " << s.unconverged_steps
      << " steps (Newton capped at " << cap << " iterations or the deadline), worst |dx|/tol "
      << s.max_unconverged << "\n"
      << "              these results depend on this machine's speed and load: a real-time\n"
      << "              run is not repeatable; every other mode is bit-identical run to run\n";
}

// The run of a prepared model, in this process: the CSV, the summary, the
// exit status.
int run_prepared(PreparedRun& prepared, const RunRequest& request, const std::string& out_path,
                 const volatile std::sig_atomic_t* stop, bool flush_rows) {
  Simulation& sim = *prepared.sim;
  std::ofstream csv;
  if (!out_path.empty()) {
    const fs::path parent = fs::path(out_path).parent_path();
    std::error_code ec;
    if (!parent.empty()) fs::create_directories(parent, ec);
    csv.open(out_path);
    if (!csv) {
      std::cerr << "monohydra: cannot write '" << out_path << "'\n";
      return 2;
    }
  }
  // What produced the results, for the sidecars of the CSV and the readings.
  ResultProvenance provenance;
  provenance.model_path = request.model_path;
  provenance.formulation = sim.formulation_name();
  provenance.integrator = sim.integrator_name();
  provenance.solver = sim.settings();
  provenance.output_interval = request.output_interval;
  provenance.real_time_cap = request.real_time_cap;
  provenance.plugins = prepared.used;
  provenance.set = request.overrides.set;
  if (!out_path.empty() && !write_sidecar(out_path, provenance)) return 2;
  // Inputs from outside and checkpoints: read and checked before any step.
  std::optional<InputFeed> feed;
  RunState resumed;
  long save_step = -1;
  try {
    if (!request.inputs.empty())
      feed = request.inputs == "-" ? InputFeed::from_stream(STDIN_FILENO)
                                   : InputFeed::from_csv(request.inputs, sim);
    if (!request.resume.empty()) load_checkpoint(request.resume, resumed);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  if (!request.save_state.empty()) {
    const double dt = sim.settings().dt;
    save_step = prepared.steps;
    if (request.save_at) {
      save_step = std::lround(*request.save_at / dt);
      if (std::abs(static_cast<double>(save_step) * dt - *request.save_at) >
              1e-9 * *request.save_at ||
          save_step < 1 || save_step > prepared.steps) {
        std::cerr << "monohydra: --at expects a time on the run's steps (a multiple of dt = " << dt
                  << " s, up to t_end = " << sim.settings().t_end << " s), got " << *request.save_at
                  << " s\n";
        return 2;
      }
    }
  }
  ProgressBar bar;
  RunOptions options;
  if (!request.stream) options.progress = std::ref(bar);
  options.stop = stop;
  options.flush_rows = flush_rows || request.stream;
  options.csv_name = request.stream ? "standard output" : out_path;
  options.layout = prepared.layout.get();
  options.real_time_cap = request.real_time_cap;
  if (!request.resume.empty()) options.resume = &resumed;
  // What the sensors read: at the run's first state (before its first step)
  // and after every step.
  std::optional<SensorSampler> sensors;
  std::ofstream sensors_csv;
  bool sensors_started = false;
  if (!request.sensors_out.empty()) {  // prepare_run refused a model without sensors
    sensors.emplace(sim, prepared.file.sensors, request.seed);
    const fs::path parent = fs::path(request.sensors_out).parent_path();
    std::error_code ec;
    if (!parent.empty()) fs::create_directories(parent, ec);
    sensors_csv.open(request.sensors_out);
    if (!sensors_csv) {
      std::cerr << "monohydra: cannot write '" << request.sensors_out << "'\n";
      return 2;
    }
    sensors->header(sensors_csv);
    ResultProvenance sensor_provenance = provenance;
    sensor_provenance.sensor_seed = request.seed;
    if (!write_sidecar(request.sensors_out, sensor_provenance)) return 2;
  }
  const auto read_sensors = [&](const Simulation& s) {
    if (sensors && sensors->sample(s)) sensors->row(sensors_csv, s.time());
  };
  options.before_step = [&](Simulation& s) {
    if (!sensors_started) read_sensors(s);
    sensors_started = true;
    if (feed) feed->apply(s);
  };
  options.after_step = [&](const Simulation& s) {
    read_sensors(s);
    if (save_step > 0 && s.step_index() == save_step) save_checkpoint(s, request.save_state);
  };
  std::ostream* rows = request.stream ? &std::cout : out_path.empty() ? nullptr : &csv;
  const RunSummary s = mh::run(sim, rows, options);
  std::ostream& report = request.stream ? std::cerr : std::cout;
  if (s.end == RunEnd::write_failed) {
    csv.close();
    drop_partial_last_line(out_path);
  }
  if (bar.enabled && s.failed) std::fputc('\n', stderr);
  // The stability check is known once the run has made it: the sidecar again, with it.
  if (!out_path.empty() && sim.explicit_stability().checks > 0) {
    provenance.stability = &sim.explicit_stability();
    if (!write_sidecar(out_path, provenance)) return 2;
  }
  if (s.end == RunEnd::bad_input) {  // nothing ran: the error alone
    std::cerr << "monohydra: " << s.failure << '\n';
    return 2;
  }
  const bool articulated = sim.settings().newton == NewtonKind::articulated;
  report << "model:        " << prepared.file.model.name << " (" << request.model_path << ")\n"
         << "formulation:  " << sim.formulation_name() << "\n"
         << "integrator:   " << sim.integrator_name() << "\n"
         << "steps:        " << s.steps << " of " << s.steps_asked
         << " asked (dt = " << sim.settings().dt << " s, t_end = " << sim.settings().t_end << " s"
         << (s.first_step > 0 ? ", from step " + std::to_string(s.first_step) : "") << ")\n"
         << "Newton:       "
         << (s.steps > 0 ? static_cast<double>(s.iterations) / static_cast<double>(s.steps) : 0.0)
         << " iterations per step on average, " << s.max_iterations << " at most\n"
         << "retries:      " << s.retries << " halvings of failed steps\n"
         << (sim.settings().line_search
                 ? "line search:  " + std::to_string(s.damped) + " increments shortened\n"
                 : std::string())
         << (sim.explicit_stability().checks > 0
                 ? "stability:    " + stability_text(sim.explicit_stability()) + " (" +
                       stability_cost_text(sim.explicit_stability()) + ")\n"
                 : std::string())
         << "solver:       "
         << (articulated ? std::string() : std::string(to_string(sim.settings().linear)) + ", ")
         << to_string(sim.settings().newton) << " Newton"
         << (sim.settings().line_search ? " with line search, " : ", ")
         << (s.steps > 0 ? static_cast<double>(s.tangents) / static_cast<double>(s.steps) : 0.0)
         << (articulated ? " articulated-body factorizations of M' per step (no tangent)\n"
                         : " tangents factored per step\n")
         << "peak |drift|: " << s.max_abs_drift << " J\n"
         << "wall time:    " << s.wall_seconds << " s\n";
  if (s.real_time) print_real_time(report, s, request.real_time_cap);
  if (!out_path.empty())
    report << "results:      " << out_path << " (" << s.rows << " rows of "
           << prepared.layout->names().size() << " columns, every "
           << prepared.layout->every_steps() << " steps)\n"
           << "provenance:   " << sidecar_path(out_path) << "\n";
  host::print_used_components(report, prepared.used);
  if (!request.save_state.empty() && s.first_step + s.steps >= save_step)
    report << "state:        " << request.save_state
           << " (t = " << static_cast<double>(save_step) * sim.settings().dt << " s; run --resume "
           << request.save_state << " goes on from there)\n";
  if (sim.explicit_stability().unstable && s.end != RunEnd::simulation_failed)
    std::cerr << "monohydra: warning: the explicit integrator '" << sim.integrator_name()
              << "' is unstable at this dt (" << stability_text(sim.explicit_stability())
              << "): its results grow without bound however bounded they look; use a step "
                 "below the bound or an implicit integrator\n";
  switch (s.end) {
    case RunEnd::completed:
      break;
    case RunEnd::simulation_failed:
      std::cerr << "monohydra: simulation failed at " << s.failure << '\n';
      return 1;
    case RunEnd::bad_input:  // reported above
    case RunEnd::write_failed:
      std::cerr << "monohydra: " << s.failure << '\n';
      return 1;
    case RunEnd::interrupted:
      std::cerr << "monohydra: interrupted by " << signal_name(s.stop_signal) << ": " << s.failure
                << (out_path.empty() ? "" : "; every row up to there is in '" + out_path + "'")
                << '\n';
      return exit_status_for_signal(s.stop_signal);
  }
  if (s.first_step + s.steps != s.steps_asked) {  // never report a run short of t_end as done
    std::cerr << "monohydra: the run did " << s.first_step + s.steps << " of " << s.steps_asked
              << " steps\n";
    return 1;
  }
  return 0;
}

// The time of the last whole row of a CSV (its first field), or NaN.
double last_row_time(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  try {
    return std::stod(last.substr(0, last.find(',')));
  } catch (const std::exception&) {
    return std::nan("");
  }
}

// `run` sets the run up and steps it in a child process: a plugin that
// crashes (a segfault in its setup or its residual) ends the child, not this
// one, which then says where the run stopped; the child flushes every CSV
// row, so every row it computed stays. A stop signal this process gets is
// passed on to the child, which stops after its current row. Without fork,
// the run is made here.
int simulate(RunRequest request, const std::string& out_path) {
  request.csv = !out_path.empty();
  start_call_watchdog(request.call_limits);  // create and setup are plugin calls too
  const volatile std::sig_atomic_t* stop = install_stop_handlers();
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  CrashReport* crash = shared_crash_report();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const auto prepared = prepare_run(request);
    return prepared ? run_prepared(*prepared, request, out_path, stop, true) : 2;
  }
  if (pid == 0) {
    install_crash_handler(crash);
    start_call_watchdog(request.call_limits);    // the parent's thread is not in the child
    const auto prepared = prepare_run(request);  // every plugin's create and setup
    if (!prepared) {
      std::cerr.flush();
      std::_Exit(2);
    }
    int code = run_prepared(*prepared, request, out_path, stop, true);
    code = with_output_written(code);
    std::cerr.flush();
    std::_Exit(code);  // the parent owns everything else: no destructors, no atexit
  }
  int status = 0;
  // A stop signal is passed on: the child stops after its row.
  if (!wait_passing_stop(pid, stop, status)) return 70;
  const std::string site = crash_site(crash);
  release_crash_report(crash);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  const int sig = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  std::string where;
  if (!out_path.empty()) {
    const double t = last_row_time(out_path);
    where = std::isnan(t) ? "; '" + out_path + "' holds no row"
                          : "; every row up to t = " + monohydra::short_number(t) + " s is in '" +
                                out_path + "'";
  }
  std::cerr << "monohydra: the run crashed (" << signal_name(sig) << ")"
            << (site.empty() ? " outside the plugin calls the host marks (in the host, or in a "
                               "thread a plugin started)"
                             : site)
            << where << '\n';
  return 1;
}

}  // namespace

int usage(int code) {
  (code == 0 ? std::cout : std::cerr) << kUsage;
  return code;
}

int plugins(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "plugins",
      "List every plugin library found, its components and ABI version, and every id that two "
      "libraries offer; with --model, the model's plugin_paths and plugins: choices too.");
  CLI::App& app = *app_holder;
  std::string model_path;
  std::vector<std::string> extra;
  app.add_option("--model", model_path, "search this model file's plugin_paths first");
  app.add_option("ARGS", extra)->group("");  // none expected: reported below
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!extra.empty()) {
    std::cerr << "monohydra: plugins takes --model FILE.yaml at most, got '" << extra.front()
              << "'\n";
    return usage(2);
  }
  ModelFile file;
  PluginRegistry registry;
  try {
    if (!model_path.empty()) file = load_model_file(model_path);
    host::load_model_plugins(file, registry);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  std::cout << "host ABI " << MH_ABI_VERSION_MAJOR << "." << MH_ABI_VERSION_MINOR << "."
            << MH_ABI_VERSION_PATCH << "; search path:";
  for (const auto& p : host::model_search_path(file)) std::cout << ' ' << p;
  std::cout << '\n';
  for (const auto& [id, library] : file.plugin_libraries)
    std::cout << "chosen by " << model_path << ": " << id << " from " << library << '\n';
  std::string library;
  for (const auto& c : registry.components()) {
    if (c.library != library) {
      library = c.library;
      std::cout << library << " (ABI " << version_text(c.abi_version) << ")\n";
    }
    std::printf("  %-12s %-20s %s (v%s)\n", to_string(c.kind), c.id.c_str(),
                c.descriptor->name != nullptr ? c.descriptor->name : "",
                c.descriptor->version != nullptr ? c.descriptor->version : "?");
  }
  // An id two libraries offer: both listed, and which one a model takes.
  const auto& all = registry.components();
  for (size_t i = 0; i < all.size(); ++i) {
    bool first = true;
    for (size_t k = 0; k < i; ++k)
      first = first && !(all[k].kind == all[i].kind && all[k].id == all[i].id);
    if (!first) continue;
    std::vector<const ComponentInfo*> offers;
    for (const auto& c : all)
      if (c.kind == all[i].kind && c.id == all[i].id) offers.push_back(&c);
    if (offers.size() < 2) continue;
    std::cout << "offered twice: " << to_string(all[i].kind) << " '" << all[i].id << "' by";
    for (const auto* c : offers) std::cout << ' ' << c->library;
    try {
      const std::string& taken = registry.find(all[i].kind, all[i].id).library;
      std::cout << "; this model takes it from " << taken << '\n';
    } catch (const PluginError&) {
      std::cout << "; a model that uses it must say which: plugins: {" << all[i].id
                << ": LIBRARY.so}\n";
    }
  }
  for (const auto& r : registry.refusals()) std::cout << "refused: " << r << '\n';
  if (registry.components().empty()) {
    std::cerr << "monohydra: no plugins found\n";
    return 1;
  }
  return 0;
}

int run(const std::vector<std::string>& args) {
  RunRequest request;
  std::string out;
  if (const auto code = parse_run_args(args, "run", request, &out)) return *code;
  if (!request.report_dir.empty()) {
    // A report is made from the whole run kept in memory, as compare makes
    // it: the options that feed, pace, stream or checkpoint a run are not
    // for it.
    const std::pair<bool, const char*> refused[] = {
        {!out.empty(), "--out (the CSV goes to DIR)"},
        {request.output_interval.has_value(), "--output-interval"},
        {request.real_time_cap > 0, "--real-time"},
        {!request.inputs.empty(), "--inputs"},
        {request.stream, "--stream"},
        {!request.save_state.empty(), "--save-state"},
        {!request.resume.empty(), "--resume"},
        {!request.sensors_out.empty(), "--sensors-out"}};
    for (const auto& [given, name] : refused)
      if (given) {
        std::cerr << "monohydra: run --report takes no " << name
                  << "; run once with it and once with --report\n";
        return 2;
      }
    CompareJob job;
    job.model_path = request.model_path;
    if (!request.formulation.empty()) job.formulations = {request.formulation};
    if (!request.integrator.empty()) job.integrators = {request.integrator};
    job.report_dir = request.report_dir;
    job.overrides = request.overrides;
    job.single_run = true;
    start_call_watchdog(request.call_limits);
    return run_comparison(job, std::cout);
  }
  return simulate(request, out);
}

// Exit 0 and "OK" when `run` would start, 1 and the error when not.
int validate(const std::vector<std::string>& args) {
  RunRequest request;
  if (const auto code = parse_run_args(args, "validate", request, nullptr)) return *code;
  start_call_watchdog(request.call_limits);
  const auto prepared = prepare_run(request);
  if (!prepared) return 1;
  try {
    prepared->sim->start();  // closes the loops, solves the initial states
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 1;
  }
  std::cout << "OK: " << request.model_path << " (" << prepared->file.model.name << ", "
            << prepared->sim->formulation_name() << ", " << prepared->sim->integrator_name()
            << "): " << prepared->steps << " steps of dt = " << prepared->sim->settings().dt
            << " s, " << prepared->columns << " columns\n";
  return 0;
}

}  // namespace mh::cli
