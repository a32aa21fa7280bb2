#include "step_overrides.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

#include "cli_support.hpp"

namespace mh::cli {

SolverSettings StepOverrides::applied_to(const SolverSettings& file) const {
  SolverSettings s = file;
  if (dt) s.dt = *dt;
  if (t_end) s.t_end = *t_end;
  if (explicit_stability) s.explicit_stability = *explicit_stability;
  return s;
}

StepOverrideOptions::StepOverrideOptions(CLI::App& app, bool limits, bool stability,
                                         const std::string& scope) {
  const std::string of = scope.empty() ? "" : " " + scope;
  dt_opt_ = app.add_option("--dt", dt_, "time step (s)" + of + ", replaces solver: dt");
  t_end_opt_ = app.add_option("--t-end", t_end_, "end time (s)" + of + ", replaces solver: t_end");
  if (limits) {
    steps_opt_ = app.add_option("--max-steps", max_steps_, "refuse runs of more steps (1e8)");
    bytes_opt_ =
        app.add_option("--max-output-bytes", max_bytes_, "refuse larger outputs (1e10 bytes)");
  }
  if (stability)
    stability_opt_ = app.add_option(
        "--explicit-stability", stability_,
        "error|warn|off: an explicit step beyond its stability bound stops the run, is reported "
        "(default, or solver: explicit_stability) or is not checked");
}

void StepOverrideOptions::add_settings(CLI::App& app) {
  set_opt_ = app.add_option("--set", set_,
                            "PATH=VALUE: set a value of the model by its path "
                            "(bodies/boom/mass=250, subsystems/valve/flow_coefficient=2e-8, "
                            "gravity/1=-9.81); repeatable")
                 ->take_all()
                 ->allow_extra_args(false);
}

bool StepOverrideOptions::read(StepOverrides& into, bool positive) const {
  if (set_opt_ != nullptr)
    for (const std::string& text : set_) {
      try {
        into.set.push_back(host::parse_setting(text));
      } catch (const std::invalid_argument& err) {
        std::cerr << "monohydra: --set " << err.what() << '\n';
        return false;
      }
    }
  for (const auto& [opt, flag, text, target] :
       {std::tuple{dt_opt_, "--dt", &dt_, &into.dt},
        std::tuple{t_end_opt_, "--t-end", &t_end_, &into.t_end}}) {
    if (opt->count() == 0) continue;
    const std::optional<double> v = parse_number(flag, *text);
    if (!v) return false;
    if (positive && (!std::isfinite(*v) || !(*v > 0.0))) {
      std::cerr << "monohydra: " << flag << " expects a positive number of seconds, got '" << *text
                << "'\n";
      return false;
    }
    *target = *v;
  }
  if (steps_opt_ != nullptr && steps_opt_->count() > 0 &&
      !parse_limit("--max-steps", max_steps_, into.limits))
    return false;
  if (bytes_opt_ != nullptr && bytes_opt_->count() > 0 &&
      !parse_limit("--max-output-bytes", max_bytes_, into.limits))
    return false;
  if (stability_opt_ != nullptr && stability_opt_->count() > 0) {
    into.explicit_stability = parse_stability_option(stability_);
    if (!into.explicit_stability) return false;
  }
  return true;
}

}  // namespace mh::cli
