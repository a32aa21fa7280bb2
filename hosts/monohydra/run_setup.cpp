#include "run_setup.hpp"

#include <iostream>

#include "cli_support.hpp"
#include "model_plugins.hpp"
#include "model_settings.hpp"
#include "monohydra/core/run.hpp"
#include "monohydra/core/sensor_sampler.hpp"

namespace mh::cli {

std::unique_ptr<PreparedRun> prepare_run(const RunRequest& request) {
  auto p = std::make_unique<PreparedRun>();
  try {
    p->file = host::load_model_file(request.model_path, request.overrides.set);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  if (!request.sensors_out.empty() && p->file.sensors.empty()) {
    std::cerr << "monohydra: --sensors-out: " << request.model_path
              << " has no sensors: (docs/model-format.md)\n";
    return nullptr;
  }
  try {
    host::load_model_plugins(p->file, p->registry);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  // --explicit-stability over the file's solver.explicit_stability.
  const StepOverrides& o = request.overrides;
  if (o.explicit_stability) p->file.solver.explicit_stability = *o.explicit_stability;
  const SettingOrigins origins = o.origins();
  try {
    // The settings are checked before any plugin reads them (the output's
    // size once the columns are known, below).
    check_run_settings(p->file, o.applied_to(p->file.solver), o.limits, 0, origins);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  try {
    p->sim = std::make_unique<Simulation>(
        p->file, p->registry, RunChoices{request.formulation, request.integrator, o.dt, o.t_end},
        log_to_stderr);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    for (const auto& r : p->registry.refusals()) std::cerr << "  (refused: " << r << ")\n";
    return nullptr;
  }
  try {
    p->layout = std::make_unique<CsvLayout>(*p->sim, p->file.output, request.output_interval,
                                            request.real_time_cap > 0);
    p->columns = p->layout->names().size();
    check_column_names(p->file, *p->sim);
    p->used = host::used_components(p->file, p->registry, request.formulation, request.integrator);
    // The sensors' columns; their rates and delays too when this run reads them.
    if (!request.sensors_out.empty() && !p->file.sensors.empty())
      SensorSampler(*p->sim, p->file.sensors, request.seed);
    else
      SensorSampler::check_columns(*p->sim, p->file.sensors);
    p->steps = check_run_settings(p->file, p->sim->settings(), o.limits,
                                  request.csv ? p->columns : 0, origins, p->layout->every_steps());
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  return p;
}

}  // namespace mh::cli
