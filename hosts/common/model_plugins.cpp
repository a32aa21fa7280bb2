#include "model_plugins.hpp"

#include <algorithm>
#include <cstdio>

#include "monohydra/core/input_error.hpp"

namespace mh::host {

std::vector<std::string> model_search_path(const ModelFile& file) {
  auto search = file.plugin_paths;
  for (const auto& path : PluginRegistry::default_search_path()) search.push_back(path);
  return search;
}

void load_model_plugins(const ModelFile& file, PluginRegistry& registry) {
  for (const auto& [id, library] : file.plugin_libraries) {
    try {
      registry.load(library);
    } catch (const PluginError& err) {
      throw InputError(SourceMark{file.path, 0, 0}, "plugins." + id, err.what());
    }
    registry.choose(id, library);
  }
  registry.scan(model_search_path(file));
}

std::vector<UsedComponent> used_components(const ModelFile& file, const PluginRegistry& registry,
                                           const std::string& formulation,
                                           const std::string& integrator) {
  std::vector<std::pair<ComponentKind, std::string>> wanted{
      {ComponentKind::formulation, formulation.empty() ? file.formulation.name : formulation},
      {ComponentKind::integrator, integrator.empty() ? file.integrator.name : integrator}};
  for (const auto& spec : file.subsystems) {
    const std::pair<ComponentKind, std::string> w{ComponentKind::subsystem, spec.type};
    if (std::find(wanted.begin(), wanted.end(), w) == wanted.end()) wanted.push_back(w);
  }
  std::vector<UsedComponent> used;
  for (const auto& [kind, id] : wanted) {
    try {
      const ComponentInfo& c = registry.find(kind, id);
      const char* version = c.descriptor->version;
      used.push_back(UsedComponent{kind, id, c.library, version != nullptr ? version : ""});
    } catch (const PluginError&) {  // the run reports it
    }
  }
  return used;
}

void print_used_components(std::ostream& out, const std::vector<UsedComponent>& used) {
  out << "plugins:\n";
  for (const auto& u : used) {
    char line[128];
    std::snprintf(line, sizeof line, "  %-12s %-20s v%-8s ", to_string(u.kind), u.id.c_str(),
                  u.version.empty() ? "?" : u.version.c_str());
    out << line << u.library << '\n';
  }
}

}  // namespace mh::host
