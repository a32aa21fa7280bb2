// monohydra sensitivities MODEL --params PATH,... : the run as `run` makes
// it, with the forward sensitivities of every coordinate, named state and
// differentiated output with respect to each parameter (sensitivities.hpp,
// docs/identification.md), as CSV: t, then d(NAME)/d(PATH) for each column
// and parameter, one row per step.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "run_setup.hpp"
#include "sensitivity_columns.hpp"
#include "step_overrides.hpp"
#include "subcommand_parser.hpp"

namespace mh::cli {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", v);
  return text;
}

}  // namespace

int sensitivities(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "sensitivities",
      "Run MODEL.yaml as `run` does and write the forward sensitivities of every coordinate, "
      "named state and output with respect to each of --params (paths as --set names them): "
      "CSV columns t and d(NAME)/d(PATH), one row per step (stdout, or --out FILE.csv).");
  CLI::App& app = *app_holder;
  std::vector<std::string> models;
  std::string params_text, out_path;
  RunRequest request;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--params", params_text,
                 "the parameters, comma-separated paths: bodies/NAME/mass, bodies/NAME/com/I, "
                 "bodies/NAME/inertia/I, gravity/I");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  app.add_option("--out", out_path, "write the CSV to FILE instead of stdout");
  StepOverrideOptions overrides(app, false, false);
  overrides.add_settings(app);
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!overrides.read(request.overrides)) return 2;
  if (models.size() != 1) {
    std::cerr << "monohydra: sensitivities needs one model file\n";
    return 2;
  }
  const std::vector<std::string> paths = split_list(params_text);
  if (paths.empty()) {
    std::cerr << "monohydra: sensitivities needs --params PATH[,PATH...]\n";
    return 2;
  }
  request.model_path = models.front();
  const auto prepared = prepare_run(request);
  if (!prepared) return 2;
  Simulation& sim = *prepared->sim;

  // Each path as the engine takes it, from the text the run was made of.
  try {
    sim.track_sensitivities(parameter_directions(request, prepared->file, paths));
  } catch (const std::invalid_argument& err) {
    std::cerr << "monohydra: --params: " << err.what() << '\n';
    return 2;
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 1;
  }

  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) {
      std::cerr << "monohydra: cannot write '" << out_path << "'\n";
      return 2;
    }
  }
  std::ostream& out = out_path.empty() ? std::cout : file;
  const std::vector<SensitivityColumn> columns = sensitivity_columns(sim);
  out << "t";
  for (const SensitivityColumn& c : columns)
    for (const std::string& path : paths) out << ",d(" << c.name << ")/d(" << path << ")";
  out << '\n';
  const auto row = [&] {
    out << number(sim.time());
    for (const SensitivityColumn& c : columns)
      for (size_t j = 0; j < paths.size(); ++j)
        out << ',' << number(column_sensitivity(sim, c, static_cast<int>(j)));
    out << '\n';
  };
  try {
    sim.start();
    row();
    for (long k = 0; k < prepared->steps; ++k) {
      sim.step();
      row();
    }
  } catch (const std::exception& err) {
    out.flush();
    std::cerr << "monohydra: " << err.what() << " (the rows before it are written)\n";
    return 1;
  }
  out.flush();
  if (!out) {
    std::cerr << "monohydra: writing the sensitivities failed\n";
    return 1;
  }
  return 0;
}

}  // namespace mh::cli
