// `monohydra check` is the test host's check_library (hosts/testhost): one
// implementation of the contract checks for the command line and for plugin
// authors' unit tests. This file parses the arguments, chooses the shipped
// models the checks fall back on and prints the lines as they come.
#include "plugin_check.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "monohydra/testhost.hpp"
#include "shipped_models.hpp"
#include "subcommand_parser.hpp"

namespace mh::cli {

int check(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "check",
      "Load PLUGIN.so and drive each of its components through its contract on MODEL.yaml "
      "(default: the component's declared example model, else the shipped four-bar, or the "
      "smallest shipped model using a subsystem): load and version, descriptors, "
      "create/destroy cycles, bad options refused, analytic tangent against differences, "
      "bit-identical reruns, snapshots restored; each check in a child process. Exit 0 when "
      "every check passed, "
      "1 when one failed.");
  CLI::App& app = *app_holder;
  std::vector<std::string> files;
  app.add_option("PLUGIN.so [MODEL.yaml]", files, "the plugin library, then the model");
  std::vector<double> at;
  app.add_option("--at", at,
                 "times (s, comma-separated) at which a subsystem's derivative blocks and a "
                 "formulation's tangent blocks are compared with differences (default: the "
                 "first step, after 3 steps, a third and two thirds into the model's run, its "
                 "last step)")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            char* end = nullptr;
            const double t = std::strtod(text.c_str(), &end);
            if (end == text.c_str() || *end != '\0' || !std::isfinite(t) || t < 0.0)
              return "a time in s at or after the run's start (0), not '" + text + "'";
            return "";
          },
          "TIME,..."));
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (files.empty() || files.size() > 2) {
    std::cerr << "usage: monohydra check PLUGIN.so [MODEL.yaml] [--at T1,T2,...]\n";
    return 2;
  }
  namespace th = monohydra::testhost;
  std::cout << "check " << files[0] << '\n';
  th::CheckOptions options;
  // This executable's shipped models (installed beside it, or the source
  // tree's from a build tree); subsystems get every one, smallest first.
  options.fallback_models = {shipped_model("fourbar.yaml"), shipped_model("double-pendulum.yaml")};
  options.models_folder = std::filesystem::path(options.fallback_models.front()).parent_path();
  options.at = at;
  options.on_check = [](const th::Check& c) {
    switch (c.verdict) {
      case th::Check::Verdict::passed:
        std::cout << "  ok    " << c.what << (c.detail.empty() ? "" : ": " + c.detail) << '\n';
        break;
      case th::Check::Verdict::failed:
        std::cout << "  FAIL  " << c.what << ": " << c.detail << '\n';
        break;
      case th::Check::Verdict::skipped:
        std::cout << "  skip  " << c.what << ": " << c.detail << '\n';
        break;
      case th::Check::Verdict::note:
        std::cout << "  on    " << c.what << ": " << c.detail << '\n';
        break;
    }
    std::cout.flush();
  };
  const th::Model model = th::Model::file(files.size() == 2 ? files[1] : "");
  const th::CheckReport report =
      th::check_library(files[0], files.size() == 2 ? &model : nullptr, options);
  if (report.bad_model) {
    std::cerr << "monohydra: the model cannot be used (above)\n";
    return 2;
  }
  if (!report.loaded) {
    std::cout << "monohydra check: FAILED (the library cannot be loaded)\n";
    return 1;
  }
  const int failures = report.failures();
  std::cout << "monohydra check: " << (failures == 0 ? "OK" : "FAILED") << " (" << failures
            << " failure" << (failures == 1 ? "" : "s") << ")\n";
  return failures == 0 ? 0 : 1;
}

}  // namespace mh::cli
