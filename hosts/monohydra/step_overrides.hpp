// --dt, --t-end, --max-steps, --max-output-bytes, --explicit-stability and
// --set: how run, validate, compare and sweep override a model's solver
// settings and values, declared, read and applied in one place.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "model_settings.hpp"
#include "monohydra/core/explicit_stability.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/run_limits.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace mh::cli {

struct StepOverrides {
  std::optional<double> dt, t_end;  // s: replace solver: dt and t_end
  RunLimits limits;
  std::optional<ExplicitStabilityPolicy> explicit_stability;  // unset: the model file's
  // --set PATH=VALUE, in the order given: values of the model by path, set in
  // its text before the parser reads it (host::load_model_file).
  std::vector<host::PathSetting> set;

  // The model file's solver settings with these replaced.
  SolverSettings applied_to(const SolverSettings& file) const;
  // Which of dt and t_end came from the command line (named in messages).
  SettingOrigins origins() const { return {dt.has_value(), t_end.has_value()}; }
};

// The options of one subcommand: add them before parsing, read them after.
class StepOverrideOptions {
 public:
  // The options a command takes: the times always, the run limits and the
  // explicit stability policy when asked; `scope` completes the times'
  // help ("of every case").
  StepOverrideOptions(CLI::App& app, bool limits, bool stability, const std::string& scope = "");
  // Into `into`; false after telling the user what is wrong. dt and t_end
  // must be numbers; their ranges are the run's checks (check_run_settings,
  // which names the flag), or, with `positive` (sweep: no model to check
  // against yet), positive numbers of seconds here.
  bool read(StepOverrides& into, bool positive = false) const;
  // Adds --set PATH=VALUE (repeatable) for the commands that open one model.
  void add_settings(CLI::App& app);

 private:
  std::string dt_, t_end_, max_steps_, max_bytes_, stability_;
  std::vector<std::string> set_;
  CLI::Option* dt_opt_ = nullptr;
  CLI::Option* t_end_opt_ = nullptr;
  CLI::Option* steps_opt_ = nullptr;
  CLI::Option* bytes_opt_ = nullptr;
  CLI::Option* stability_opt_ = nullptr;
  CLI::Option* set_opt_ = nullptr;
};

}  // namespace mh::cli
