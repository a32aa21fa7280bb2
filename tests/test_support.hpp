// What the tests share: the build's plugin registry and models from text.
#pragma once

#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include "build_paths.hpp"
#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/subsystem.h"

namespace mh::test {

// A registry holding the plugins of this build (loaded once per process).
inline const PluginRegistry& build_plugins() {
  static const std::unique_ptr<PluginRegistry> registry = [] {
    auto r = std::make_unique<PluginRegistry>();
    r->scan({mh::test::paths::plugin_dir});
    return r;
  }();
  return *registry;
}

// A registry holding the plugin library at `library` and then the plugins of
// this build, as the example tests need it: loaded once per path and process
// (the tests call it from one thread).
inline const PluginRegistry& build_plugins_with(const std::string& library) {
  static std::map<std::string, std::unique_ptr<PluginRegistry>> registries;
  std::unique_ptr<PluginRegistry>& registry = registries[library];
  if (registry == nullptr) {
    auto r = std::make_unique<PluginRegistry>();
    r->load(library);
    r->scan({mh::test::paths::plugin_dir});
    registry = std::move(r);
  }
  return *registry;
}

// Why a fresh registry refuses the library at `path` ("" when it loads).
inline std::string load_error(const std::string& path) {
  PluginRegistry r;
  try {
    r.load(path);
  } catch (const PluginError& e) {
    return e.what();
  }
  return "";
}

inline std::string source_path(const std::string& relative) {
  return std::string(mh::test::paths::source_dir) + "/" + relative;
}

// The example model a subsystem component of this build declares (its
// factory's example_model), "" when it declares none.
inline std::string example_model(const std::string& id) {
  const ComponentInfo& c = build_plugins().find(ComponentKind::subsystem, id);
  const auto* plugin = static_cast<const mh_subsystem_factory*>(c.factory);
  if (c.subsystem_factory.count == nullptr || c.subsystem_factory.example_model == nullptr)
    return "";
  for (uint32_t i = 0; i < c.subsystem_factory.count(plugin); ++i)
    if (id == c.subsystem_factory.descriptor(plugin, i)->id) {
      const char* text = c.subsystem_factory.example_model(plugin, i);
      return text != nullptr ? text : "";
    }
  return "";
}

// `text` with its first `from` replaced by `to`; "" when `from` is not there
// (so that a model edited wrongly fails to parse, loudly).
inline std::string edited(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) return "";
  return text.replace(at, from.size(), to);
}

// For RecordProperty: an error or a measured number, in a readable form.
inline std::string scientific(double x) {
  std::ostringstream out;
  out << std::scientific << x;
  return out.str();
}

}  // namespace mh::test
