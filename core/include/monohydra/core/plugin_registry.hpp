// Finds plugin libraries, loads them with Boost.DLL through their one entry
// symbol, checks their ABI version, and lists the components they offer.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "monohydra/formulation.h"
#include "monohydra/integrator.h"
#include "monohydra/subsystem.h"

namespace mh {

class ProbeCache;

// A library that could not be used as a plugin, and why.
class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ComponentKind { formulation, subsystem, integrator };

struct ComponentInfo {
  ComponentKind kind;
  std::string id;
  const mh_component_descriptor* descriptor = nullptr;
  mh_version abi_version{};  // of the library that holds it
  std::string library;       // path of that library
  // The factory that creates it, read up to its struct_size (abi_struct.hpp):
  // the one of its kind is set.
  mh_formulation_factory formulation_factory{};
  mh_subsystem_factory subsystem_factory{};
  mh_integrator_factory integrator_factory{};
  const void* factory = nullptr;  // the plugin's own pointer, passed back to its calls
};

class PluginRegistry {
 public:
  PluginRegistry();
  ~PluginRegistry();
  PluginRegistry(const PluginRegistry&) = delete;
  PluginRegistry& operator=(const PluginRegistry&) = delete;

  // The default search path, in order: $MONOHYDRA_PLUGIN_PATH (':'-separated),
  // when the engine is a shared library (the embedding API) the plugin
  // folder beside it (monohydra/plugins), the plugin folder beside the
  // running executable (../lib/monohydra/plugins), and the install prefix's.
  static std::vector<std::string> default_search_path();

  // Loads one library. It is first probed in a forked child (plugin_probe.hpp;
  // verdicts cached, probe_cache.hpp): throws PluginError naming the file when
  // the child crashed or hung, or when it is not a shared library, lacks the entry symbol, was
  // built for another ABI major version or fails to initialise. A component id that another
  // library offers too is kept from both: find() then needs a choice (choose()). A
  // byte-identical copy of a loaded library (the same plugin installed twice) is skipped.
  void load(const std::string& path);
  // Loads every shared library (*.so) in the folders, in order, skipping a
  // library already loaded from the same file. Libraries that refuse are
  // remembered in refusals() rather than thrown.
  void scan(const std::vector<std::string>& folders);
  const std::vector<std::string>& refusals() const { return refusals_; }

  const std::vector<ComponentInfo>& components() const { return components_; }
  // Throws PluginError "unknown formulation 'x' (found: a, b)" when absent, and
  // when two libraries offer the id and choose() named neither of them.
  const ComponentInfo& find(ComponentKind kind, const std::string& id) const;
  // The library to take a component id from when several offer it (a model
  // file's plugins: map); `library` is a file path. Ids never offered twice
  // ignore it, but a choice of a library that does not offer the id is an
  // error at find().
  void choose(const std::string& id, const std::string& library);

 private:
  struct Library;
  void load_library(const std::string& path);
  std::unique_ptr<ProbeCache> probe_cache_;
  std::vector<std::unique_ptr<Library>> libraries_;
  std::vector<ComponentInfo> components_;
  std::vector<std::string> refusals_;
  std::vector<std::pair<std::string, std::string>> choices_;  // id, canonical library path
};

const char* to_string(ComponentKind kind);

}  // namespace mh
