// monohydra fit MODEL --data MEASURED.csv --params PATH,... : the parameters'
// values that make the model's columns best match the measured ones
// (docs/identification.md). Everything is checked before the first run; the
// files of --out are written only when the fit is done, each whole.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "fit_report.hpp"
#include "fit_statistics.hpp"
#include "least_squares.hpp"
#include "measured_data.hpp"
#include "model_settings.hpp"
#include "monohydra/core/input_error.hpp"
#include "monohydra/core/model_text.hpp"
#include "run_setup.hpp"
#include "sampled_run.hpp"
#include "step_overrides.hpp"
#include "subcommand_parser.hpp"

namespace fs = std::filesystem;

namespace mh::cli {

namespace {

// DIR/name written whole: to a hidden file first, then renamed over it.
void write_whole(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path partial = dir / ("." + name + ".partial");
  {
    std::ofstream out(partial, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(partial, ignored);
      throw std::runtime_error("cannot write '" + (dir / name).string() + "'");
    }
  }
  fs::rename(partial, dir / name);
}

}  // namespace

int fit(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "fit",
      "Fit the parameters --params of MODEL.yaml to the columns of --data MEASURED.csv by "
      "nonlinear least squares on the exact sensitivities: each estimate with its standard "
      "error, 95 % interval and whether the data determine it; --out DIR writes "
      "estimates.csv, fitted.yaml and report.html.");
  CLI::App& app = *app_holder;
  std::vector<std::string> models, noise_texts;
  std::string data_path, params_text, out_dir, iterations_text = "50";
  RunRequest request;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--data", data_path,
                 "CSV: t, then columns named as `run` names them (or as the model's sensors); an "
                 "empty field is a sample not taken");
  app.add_option("--params", params_text,
                 "the parameters, comma-separated paths as --set names them: bodies/NAME/mass, "
                 "subsystems/NAME/OPTION, gravity/I, ...");
  app.add_option("--noise", noise_texts,
                 "COLUMN=SIGMA: the measured column's noise level (its standard deviation, SI); "
                 "default the model's sensor of that name, else the column's residual RMS at the "
                 "solution");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  app.add_option("--max-iterations", iterations_text,
                 "Levenberg-Marquardt iterations per round of weights (default 50)");
  app.add_option("--out", out_dir, "write DIR/estimates.csv, DIR/fitted.yaml, DIR/report.html");
  StepOverrideOptions overrides(app, false, false);
  overrides.add_settings(app);
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!overrides.read(request.overrides)) return 2;
  if (models.size() != 1) {
    std::cerr << "monohydra: fit needs one model file\n";
    return 2;
  }
  const std::vector<std::string> paths = split_list(params_text);
  if (paths.empty() || data_path.empty()) {
    std::cerr << "monohydra: fit needs --data MEASURED.csv and --params PATH[,PATH...]\n";
    return 2;
  }
  const std::optional<double> iterations = parse_number("--max-iterations", iterations_text);
  if (!iterations) return 2;
  if (!(*iterations >= 1 && *iterations <= 10000 && std::floor(*iterations) == *iterations)) {
    std::cerr << "monohydra: --max-iterations: a whole number from 1 to 10000\n";
    return 2;
  }
  request.model_path = models.front();

  // Everything checked before the first run.
  MeasuredData data;
  std::unique_ptr<SampledRun> run;
  std::vector<double> noise;
  try {
    data = read_measured_data(data_path);
    run = std::make_unique<SampledRun>(request, paths, data);
    for (const MeasuredColumn& c : run->columns()) noise.push_back(c.noise);
    for (const std::string& text : noise_texts) {
      const host::PathSetting s = host::parse_setting(text);
      size_t c = 0;
      while (c < data.names.size() && data.names[c] != s.path) ++c;
      if (c == data.names.size())
        throw std::invalid_argument("--noise " + text + ": '" + s.path + "' is not a column of " +
                                    data_path);
      const std::optional<double> sigma = parse_number("--noise " + s.path, s.value);
      if (!sigma) return 1;
      if (!(*sigma > 0.0 && std::isfinite(*sigma)))
        throw std::invalid_argument("--noise " + text + ": a standard deviation above 0");
      noise[c] = *sigma;
    }
    if (run->samples().size() <= paths.size())
      throw std::invalid_argument(data_path + ": " + std::to_string(run->samples().size()) +
                                  " samples for " + std::to_string(paths.size()) +
                                  " parameters: a fit needs more samples than parameters");
    if (!out_dir.empty()) fs::create_directories(out_dir);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 1;
  }

  const FitResult result = fit_parameters(*run, noise, static_cast<int>(*iterations));
  if (!result.solved) {
    std::cerr << "monohydra: fit: " << result.why << '\n';
    return 1;
  }
  const FitStatistics statistics =
      fit_statistics(run->initial(), result.estimate, result.jacobian, result.sigmas_estimated);
  const FitOutcome outcome{run.get(), &data, &result, &statistics, request.model_path};
  std::cout << "monohydra fit: " << request.model_path << " against " << data_path << ": "
            << run->samples().size() << " samples in " << data.names.size() << " columns, "
            << paths.size() << " parameters; " << result.iterations
            << " Levenberg-Marquardt iterations, " << result.rounds << " round(s) of weights\n\n"
            << render_text(estimates_table(outcome)) << '\n'
            << render_text(correlation_table(outcome)) << '\n'
            << render_text(residual_table(outcome));
  if (!out_dir.empty()) {
    try {
      std::string text = read_model_text(request.model_path);
      text = host::apply_settings(text, request.model_path, run->settings_at(result.estimate)).text;
      write_whole(out_dir, "estimates.csv", estimates_csv(outcome));
      write_whole(out_dir, "fitted.yaml", text);
      write_whole(out_dir, "report.html", fit_report_html(outcome));
    } catch (const std::exception& err) {
      std::cerr << "monohydra: --out: " << err.what() << '\n';
      return 1;
    }
    std::cout << "\nwrote " << (fs::path(out_dir) / "estimates.csv").string() << ", fitted.yaml, "
              << "report.html\n";
  }
  return 0;
}

}  // namespace mh::cli
