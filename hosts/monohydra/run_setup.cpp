#include "run_setup.hpp"

#include <algorithm>
#include <iostream>
#include <sstream>

#include "cli_support.hpp"
#include "monohydra/core/run.hpp"

namespace mh::cli {

std::unique_ptr<PreparedRun> prepare_run(const RunRequest& request) {
  auto p = std::make_unique<PreparedRun>();
  try {
    p->file = load_model_file(request.model_path);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  auto search = p->file.plugin_paths;
  for (const auto& path : PluginRegistry::default_search_path()) search.push_back(path);
  p->registry.scan(search);
  try {
    p->sim = std::make_unique<Simulation>(p->file, p->registry, request.formulation, log_to_stderr);
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    for (const auto& r : p->registry.refusals()) std::cerr << "  (refused: " << r << ")\n";
    return nullptr;
  }
  if (request.dt) p->sim->settings().dt = *request.dt;
  if (request.t_end) p->sim->settings().t_end = *request.t_end;
  std::ostringstream header;
  write_csv_header(header, *p->sim);
  const std::string text = header.str();
  p->columns = static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1;
  try {
    check_column_names(p->file, *p->sim);
    p->steps = check_run_settings(
        p->file, p->sim->settings(), request.limits, request.csv ? p->columns : 0,
        SettingOrigins{request.dt.has_value(), request.t_end.has_value()});
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return nullptr;
  }
  return p;
}

}  // namespace mh::cli
