// A model's plugins: the libraries its plugins: map chooses, its plugin_paths,
// then the default search path; and which library each component a run uses
// came from, so the host can say what it loaded.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"

namespace mh::host {

struct UsedComponent {
  ComponentKind kind;
  std::string id;
  std::string library;  // canonical path
  std::string version;  // the component's descriptor version ("" when it says none)
};

// The folders searched for a model's plugins, in order.
std::vector<std::string> model_search_path(const ModelFile& file);

// Loads the libraries of the model's plugins: map (each then chosen for its
// id) and scans model_search_path. Throws InputError naming plugins.ID when a
// chosen library cannot be loaded.
void load_model_plugins(const ModelFile& file, PluginRegistry& registry);

// The formulation, the integrator and each subsystem type of the model, found
// as the simulation finds them; one that cannot be found is left out (the
// run's own error says why).
std::vector<UsedComponent> used_components(const ModelFile& file, const PluginRegistry& registry,
                                           const std::string& formulation,
                                           const std::string& integrator);

// "plugins:" then a line per component: kind, id, version and library.
void print_used_components(std::ostream& out, const std::vector<UsedComponent>& used);

}  // namespace mh::host
