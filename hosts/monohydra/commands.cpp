#include "commands.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "cli_support.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/simulation.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

const char* kUsage =
    "usage: monohydra [COMMAND] [ARGS]\n"
    "  (no command)            the paper's comparison: its case studies (models/paper-\n"
    "                          reference.yaml), the paper's numbers beside ours; reports in out/\n"
    "  plugins                 list every plugin found, its components and ABI version\n"
    "  run MODEL.yaml [--formulation NAME] [--integrator NAME] [--dt S] [--t-end S]\n"
    "                 [--out FILE.csv]\n"
    "                          simulate MODEL.yaml; CSV columns: t, z1..zN, states,\n"
    "                          outputs, KE, PE, W, drift, phi_norm, iters\n"
    "  compare MODEL.yaml [--formulations A,B,...] [--integrators C,D,...] [--report DIR]\n"
    "                     [--dt S] [--t-end S]\n"
    "                          run every formulation with every integrator on MODEL.yaml\n"
    "                          (default: the model file's compare: lists, else its own\n"
    "                          choice) and print their numbers side by side; --report\n"
    "                          writes DIR/report.html with the paper's figures and each\n"
    "                          run's CSV, named after what varies\n"
    "plugins are searched in $MONOHYDRA_PLUGIN_PATH, beside the executable, the install\n"
    "prefix and the model file's plugin_paths.\n";

std::string version_text(const mh_version& v) {
  return std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch);
}

int simulate(const std::string& model_path, const RunChoices& choices,
             const std::string& out_path) {
  ModelFile file;
  try {
    file = load_model_file(model_path);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  PluginRegistry registry;
  auto search = file.plugin_paths;
  for (const auto& p : PluginRegistry::default_search_path()) search.push_back(p);
  registry.scan(search);
  std::unique_ptr<Simulation> sim;
  try {
    sim = std::make_unique<Simulation>(file, registry, choices, log_to_stderr);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    for (const auto& r : registry.refusals()) std::cerr << "  (refused: " << r << ")\n";
    return 2;
  }
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
  ProgressBar bar;
  const RunSummary s = mh::run(*sim, out_path.empty() ? nullptr : &csv, std::ref(bar));
  if (bar.enabled && s.failed) std::fputc('\n', stderr);
  std::cout << "model:        " << file.model.name << " (" << model_path << ")\n"
            << "formulation:  " << sim->formulation_name() << "\n"
            << "integrator:   " << sim->integrator_name() << "\n"
            << "steps:        " << s.steps << " of dt = " << sim->settings().dt << " s\n"
            << "Newton:       "
            << (s.steps > 0 ? static_cast<double>(s.iterations) / static_cast<double>(s.steps)
                            : 0.0)
            << " iterations per step on average, " << s.max_iterations << " at most\n"
            << "peak |drift|: " << s.max_abs_drift << " J\n"
            << "wall time:    " << s.wall_seconds << " s\n";
  if (!out_path.empty()) std::cout << "results:      " << out_path << "\n";
  if (s.failed) {
    std::cerr << "monohydra: simulation failed at " << s.failure << '\n';
    return 1;
  }
  return 0;
}

}  // namespace

int usage(int code) {
  (code == 0 ? std::cout : std::cerr) << kUsage;
  return code;
}

int plugins(const std::vector<std::string>& args) {
  if (!args.empty()) return usage(2);
  PluginRegistry registry;
  const auto search = PluginRegistry::default_search_path();
  registry.scan(search);
  std::cout << "host ABI " << MH_ABI_VERSION_MAJOR << "." << MH_ABI_VERSION_MINOR << "."
            << MH_ABI_VERSION_PATCH << "; search path:";
  for (const auto& p : search) std::cout << ' ' << p;
  std::cout << '\n';
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
  for (const auto& r : registry.refusals()) std::cout << "refused: " << r << '\n';
  if (registry.components().empty()) {
    std::cerr << "monohydra: no plugins found\n";
    return 1;
  }
  return 0;
}

int run(const std::vector<std::string>& args) {
  std::string model, out;
  RunChoices choices;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool has_value = i + 1 < args.size();
    if ((a == "--formulation" || a == "--integrator" || a == "--dt" || a == "--t-end" ||
         a == "--out") &&
        !has_value) {
      std::cerr << "monohydra: " << a << " expects a value\n";
      return 2;
    }
    if (a == "--formulation") {
      choices.formulation = args[++i];
    } else if (a == "--integrator") {
      choices.integrator = args[++i];
    } else if (a == "--out") {
      out = args[++i];
    } else if (a == "--dt") {
      choices.dt = parse_number(a, args[++i]);
      if (!choices.dt) return 2;
    } else if (a == "--t-end") {
      choices.t_end = parse_number(a, args[++i]);
      if (!choices.t_end) return 2;
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "monohydra: unknown option '" << a << "'\n";
      return usage(2);
    } else if (model.empty()) {
      model = a;
    } else {
      std::cerr << "monohydra: one model file at a time (got '" << model << "' and '" << a
                << "')\n";
      return 2;
    }
  }
  if (model.empty()) {
    std::cerr << "monohydra: run needs a model file\n";
    return usage(2);
  }
  return simulate(model, choices, out);
}

}  // namespace mh::cli
