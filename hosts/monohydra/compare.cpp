#include "compare.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>
#include <utility>

#include "cli_support.hpp"
#include "commands.hpp"
#include "comparison.hpp"
#include "comparison_table.hpp"
#include "control_intervals.hpp"
#include "isolated_run.hpp"
#include "machine_view.hpp"
#include "model_plugins.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "report_figures.hpp"
#include "report_html.hpp"
#include "result_sidecar.hpp"
#include "run_record.hpp"
#include "stability_text.hpp"
#include "stop_signals.hpp"
#include "subcommand_parser.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

// A run's label as a file name: anything but [A-Za-z0-9._+-] becomes '_'.
std::string file_stem(const std::string& label) {
  std::string out = label;
  for (char& ch : out) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '.' || ch == '_' || ch == '-' || ch == '+';
    if (!ok) ch = '_';
  }
  return out;
}

// "A,B,C" of an option (`flag` names it in errors) as names.
std::optional<std::vector<std::string>> split_names(const std::string& flag,
                                                    const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string name; std::getline(ss, name, ',');) {
    const auto b = name.find_first_not_of(' '), e = name.find_last_not_of(' ');
    if (b == std::string::npos) {
      std::cerr << "monohydra: " << flag << " expects names separated by commas, got '" << list
                << "'\n";
      return std::nullopt;
    }
    name = name.substr(b, e - b + 1);
    if (std::find(out.begin(), out.end(), name) != out.end()) {
      std::cerr << "monohydra: " << flag << " names '" << name << "' twice\n";
      return std::nullopt;
    }
    out.push_back(name);
  }
  if (out.empty()) {
    std::cerr << "monohydra: " << flag << " expects at least one name\n";
    return std::nullopt;
  }
  return out;
}

// The list the command line gave, else the model file's compare default, else
// the model's own choice.
std::vector<std::string> or_defaults(const std::vector<std::string>& given,
                                     const std::vector<std::string>& file_defaults,
                                     const std::string& model_choice) {
  if (!given.empty()) return given;
  if (!file_defaults.empty()) return file_defaults;
  return {model_choice};
}

// A run is named after what varies: the formulation F, the integrator I, or "F+I".
std::string run_label(const std::string& formulation, const std::string& integrator,
                      bool formulations_vary, bool integrators_vary) {
  if (formulations_vary && integrators_vary) return formulation + "+" + integrator;
  return integrators_vary ? integrator : formulation;
}

std::string interval_text(const std::vector<PlotInterval>& intervals) {
  std::string text;
  char buf[64];
  for (const auto& iv : intervals) {
    std::snprintf(buf, sizeof(buf), "%s%.3f .. %.3f s", text.empty() ? "" : ", ", iv.begin, iv.end);
    text += buf;
  }
  return text;
}

}  // namespace

int run_comparison(const CompareJob& job, std::ostream& out) {
  ModelFile file;
  try {
    file = host::load_model_file(job.model_path, job.overrides.set);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  const StepOverrides& o = job.overrides;
  try {  // steps and limits before any formulation runs (rows are kept in memory)
    check_run_settings(file, o.applied_to(file.solver), o.limits, 0, o.origins());
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  if (!job.report_dir.empty()) {
    std::error_code ec;
    fs::create_directories(job.report_dir, ec);
    if (ec || !fs::is_directory(job.report_dir)) {
      std::cerr << "monohydra: cannot create the report folder '" << job.report_dir << "'\n";
      return 2;
    }
  }
  // --explicit-stability over the file's solver.explicit_stability.
  if (o.explicit_stability) file.solver.explicit_stability = *o.explicit_stability;
  // A case study of the paper runs with the paper's Newton (paper-reference.yaml).
  if (job.study != nullptr && job.study->newton) file.solver.newton = *job.study->newton;
  PluginRegistry registry;
  try {
    host::load_model_plugins(file, registry);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }

  const std::string name = job.study != nullptr ? job.study->name : file.model.name;
  const std::vector<std::string> none;
  const auto formulations = or_defaults(
      job.formulations, job.single_run ? none : file.compare_formulations, file.formulation.name);
  const auto integrators = or_defaults(
      job.integrators, job.single_run ? none : file.compare_integrators, file.integrator.name);
  std::vector<RunRecord> runs;
  std::vector<host::UsedComponent> loaded;  // every component of every run, once
  for (const auto& formulation : formulations) {
    for (const auto& integrator : integrators) {
      const std::string label =
          run_label(formulation, integrator, formulations.size() > 1, integrators.size() > 1);
      RecordOptions options;
      options.overrides = o;
      options.stop = install_stop_handlers();
      options.log = [&label](mh_log_level level, const std::string& source,
                             const std::string& msg) {
        log_to_stderr(level, "[" + label + "] " + source, msg);
      };
      ProgressBar bar;
      if (bar.enabled) {
        std::cerr << name << ": " << label << '\n';
        options.progress = std::ref(bar);
      }
      if (!job.report_dir.empty()) {
        options.csv_path = (fs::path(job.report_dir) / (file_stem(label) + ".csv")).string();
        std::error_code ec;
        fs::remove(options.csv_path, ec);  // no stale results of an earlier comparison
      }
      runs.push_back(
          record_run_isolated(file, registry, formulation, integrator, std::move(options)));
      runs.back().label = label;
      const auto used = host::used_components(file, registry, formulation, integrator);
      for (const auto& u : used)
        if (std::find_if(loaded.begin(), loaded.end(), [&u](const host::UsedComponent& l) {
              return l.kind == u.kind && l.id == u.id;
            }) == loaded.end())
          loaded.push_back(u);
      const std::string& csv = runs.back().csv_path;
      if (!csv.empty() && fs::exists(csv)) {
        ResultProvenance provenance;
        provenance.model_path = job.model_path;
        provenance.formulation = formulation;
        provenance.integrator = integrator;
        provenance.solver = file.solver;
        provenance.solver.dt =
            runs.back().dt > 0.0 ? runs.back().dt : o.dt.value_or(file.solver.dt);
        provenance.solver.t_end =
            runs.back().dt > 0.0 ? runs.back().t_end : o.t_end.value_or(file.solver.t_end);
        provenance.plugins = used;
        provenance.set = job.overrides.set;
        provenance.stability = &runs.back().stability;
        if (!write_sidecar(csv, provenance)) return 2;
      }
      if (bar.enabled && runs.back().failed && runs.back().rows() > 0) std::cerr << '\n';
      if (runs.back().failed)
        std::cerr << "monohydra: " << label << " failed on " << name << ": " << runs.back().failure
                  << (runs.back().crash_site.empty() ? "" : ";" + runs.back().crash_site) << '\n';
      if (runs.back().stopped_by != 0) break;
    }
    if (!runs.empty() && runs.back().stopped_by != 0) break;
  }

  const int stopped_by = runs.back().stopped_by;
  const Comparison c = summarize(name, job.model_path, std::move(runs));
  const PaperNumbers* paper = job.study != nullptr ? &job.study->paper : nullptr;
  const TextTable table = comparison_table(c, paper);
  out << render_text(table);
  // An explicit integrator's stability check, under the table: a bounded
  // run can still be an unstable one (docs/integrators.md).
  std::vector<std::string> stability_lines;
  for (const auto& r : c.runs)
    if (r.stability.checks > 0)
      stability_lines.push_back(r.label + " " + stability_text(r.stability));
  for (const auto& line : stability_lines) out << "explicit step: " << line << '\n';
  host::print_used_components(out, loaded);

  if (!job.report_dir.empty()) {
    std::vector<ControlColumn> controls;
    std::vector<PlotInterval> on;
    if (const RunRecord* ref = c.reference_run()) {
      controls = control_columns(*ref);
      on = control_on_intervals(*ref, controls);
    }
    const std::string shading = job.study != nullptr ? job.study->control_shading : "#d8c8f0";
    const auto figures = report_figures(file, c, on, shading);
    ReportPage page;
    page.title = std::string(job.single_run ? "monohydra run: " : "monohydra compare: ") + name;
    const auto joined = [](const std::vector<std::string>& names) {
      std::string text;
      for (const auto& f : names) text += (text.empty() ? "" : ", ") + f;
      return text;
    };
    page.facts.push_back("model: " + file.model.name + " (" + job.model_path + ")");
    page.facts.push_back("formulations: " + joined(formulations));
    page.facts.push_back("integrators: " + joined(integrators));
    for (const auto& line : stability_lines) page.facts.push_back("explicit step: " + line);
    std::vector<std::string> control_names;
    control_names.reserve(controls.size());
    for (const auto& col : controls) control_names.push_back(col.name);
    if (controls.empty())
      page.facts.push_back("control signals: the model declares none, so no interval is shaded");
    else if (on.empty())
      page.facts.push_back("control signals (" + joined(control_names) + "): never on in this run");
    else
      page.facts.push_back("control signals (" + joined(control_names) +
                           ") on, shaded in the time plots: " + interval_text(on));
    page.table = &table;
    page.figures = &figures;
    std::vector<const RunRecord*> shown;
    for (const auto& r : c.runs) shown.push_back(&r);
    add_machine_view(page, file, registry, shown, formulations);
    for (const auto& r : c.runs)
      if (!r.csv_path.empty()) page.csv_files.push_back(fs::path(r.csv_path).filename().string());
    try {
      const std::string html = write_report(job.report_dir, page);
      out << "report: " << html << '\n';
    } catch (const std::exception& err) {
      std::cerr << "monohydra: " << err.what() << '\n';
      return 2;
    }
    for (const auto& r : c.runs)
      if (!r.csv_path.empty())
        out << "csv:    " << r.csv_path << " (provenance: " << sidecar_path(r.csv_path) << ")\n";
  }
  if (stopped_by != 0) {
    std::cerr << "monohydra: interrupted by " << signal_name(stopped_by) << '\n';
    return exit_status_for_signal(stopped_by);
  }
  return c.any_failed() ? 1 : 0;
}

int compare(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "compare",
      "Run every formulation with every integrator on MODEL.yaml (default: the model file's "
      "compare: lists, else its own choice) and print their numbers side by side; the first "
      "pair is the reference.");
  CLI::App& app = *app_holder;
  CompareJob job;
  std::vector<std::string> models;
  std::string formulations, integrators;
  app.add_option("MODEL.yaml", models, "the model file");
  auto* f_opt = app.add_option("--formulations", formulations, "A,B,...: the formulations run");
  auto* i_opt = app.add_option("--integrators", integrators, "C,D,...: the integrators run");
  app.add_option("--report", job.report_dir,
                 "write DIR/report.html with the paper's figures and each run's CSV (with its "
                 "NAME.meta.json), named after what varies");
  StepOverrideOptions overrides(app, true, true);
  overrides.add_settings(app);
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (!overrides.read(job.overrides)) return 2;
  if (models.size() > 1) {
    std::cerr << "monohydra: compare takes one model file (got '" << models[0] << "' and '"
              << models[1] << "')\n";
    return 2;
  }
  if (models.empty()) {
    std::cerr << "monohydra: compare needs a model file\n";
    return usage(2);
  }
  job.model_path = models.front();
  if (f_opt->count() > 0) {
    const auto names = split_names("--formulations", formulations);
    if (!names) return 2;
    job.formulations = *names;
  }
  if (i_opt->count() > 0) {
    const auto names = split_names("--integrators", integrators);
    if (!names) return 2;
    job.integrators = *names;
  }
  // The paper's numbers go beside ours when the model is one of its case studies.
  std::vector<CaseStudy> studies;
  try {
    studies = load_case_studies(case_studies_path());
  } catch (const std::exception& err) {
    std::cerr << "monohydra: warning: no paper numbers: " << err.what() << '\n';
  }
  job.study = find_case_study(studies, job.model_path);
  return run_comparison(job, std::cout);
}

}  // namespace mh::cli
