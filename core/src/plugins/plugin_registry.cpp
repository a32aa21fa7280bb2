#include "monohydra/core/plugin_registry.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "monohydra/entry.h"
#include "plugins/abi_struct.hpp"
#include "plugins/plugin_probe.hpp"
#include "plugins/probe_cache.hpp"

namespace fs = std::filesystem;

namespace mh {

struct PluginRegistry::Library {
  std::string path;
  boost::dll::shared_library library;
  const mh_plugin_entry* entry = nullptr;
  ~Library() {
    if (entry != nullptr && entry->deinit != nullptr) entry->deinit();
  }
};

const char* to_string(ComponentKind kind) {
  switch (kind) {
    case ComponentKind::formulation:
      return "formulation";
    case ComponentKind::integrator:
      return "integrator";
    case ComponentKind::subsystem:
      break;
  }
  return "subsystem";
}

namespace {

// What model files, results (JSON) and logs quote of a component: its id and
// version at most kMaxIdBytes, its other texts at most kMaxTextBytes, each
// valid UTF-8 without control characters, an id without spaces either.
constexpr size_t kMaxIdBytes = 64;
constexpr size_t kMaxTextBytes = 4096;

// The length of a valid UTF-8 sequence at s (at most `left` bytes), or 0.
size_t utf8_sequence(const unsigned char* s, size_t left) {
  const unsigned char c = s[0];
  size_t n = 0;
  uint32_t code = 0;
  if (c < 0x80) return 1;
  if ((c & 0xE0) == 0xC0) {
    n = 2;
    code = c & 0x1Fu;
  } else if ((c & 0xF0) == 0xE0) {
    n = 3;
    code = c & 0x0Fu;
  } else if ((c & 0xF8) == 0xF0) {
    n = 4;
    code = c & 0x07u;
  } else {
    return 0;
  }
  if (n > left) return 0;
  for (size_t i = 1; i < n; ++i) {
    if ((s[i] & 0xC0) != 0x80) return 0;
    code = (code << 6) | (s[i] & 0x3Fu);
  }
  const uint32_t least[5] = {0, 0, 0x80, 0x800, 0x10000};  // no overlong forms
  if (code < least[n] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

// "" when `text` may be quoted, else what is wrong with it, with the numbers.
std::string text_problem(const char* text, size_t max_bytes, bool is_id) {
  if (text == nullptr) return is_id ? "is NULL" : "";
  const size_t length = strnlen(text, kMaxMeasuredText);
  if (length == 0 && is_id) return "is empty";
  if (length > max_bytes)
    return "is " + std::to_string(length) + " bytes long (at most " + std::to_string(max_bytes) +
           ")";
  const auto* s = reinterpret_cast<const unsigned char*>(text);
  for (size_t i = 0; i < length;) {
    const size_t n = utf8_sequence(s + i, length - i);
    if (n == 0) return "is not valid UTF-8 (byte " + std::to_string(i) + ")";
    if (n == 1 && (s[i] < 0x20 || s[i] == 0x7F) && !((s[i] == '\n' || s[i] == '\t') && !is_id))
      return "holds the control character " + std::to_string(s[i]) + " at byte " +
             std::to_string(i);
    if (is_id && s[i] == ' ') return "holds a space at byte " + std::to_string(i);
    i += n;
  }
  return "";
}

// The descriptor's texts, each checked: the first problem, naming the field.
std::string descriptor_problem(const mh_component_descriptor& d) {
  const struct {
    const char* field;
    const char* text;
    size_t max;
    bool id;
  } fields[] = {{"id", d.id, kMaxIdBytes, true},
                {"version", d.version, kMaxIdBytes, false},
                {"name", d.name, kMaxTextBytes, false},
                {"vendor", d.vendor, kMaxTextBytes, false},
                {"description", d.description, kMaxTextBytes, false}};
  for (const auto& f : fields) {
    const std::string problem = text_problem(f.text, f.max, f.id);
    if (!problem.empty()) return std::string("its ") + f.field + " " + problem;
  }
  return "";
}

// The components a factory lists. Every factory starts with struct_size,
// count, descriptor, create: read up to its struct_size, a factory without
// them lists nothing.
template <class Factory>
void list_components(const void* raw, ComponentKind kind, Factory ComponentInfo::*slot,
                     const mh_version& v, const std::string& library, const std::string& path,
                     std::vector<ComponentInfo>& found) {
  if (raw == nullptr) return;
  const auto* plugin_factory = static_cast<const Factory*>(raw);
  const Factory f = read_struct(plugin_factory);
  if (f.count == nullptr || f.descriptor == nullptr || f.create == nullptr)
    throw PluginError("'" + path + "' has an incomplete " + to_string(kind) +
                      " factory (count, descriptor or create is missing)");
  const uint32_t count = f.count(plugin_factory);
  // A library lists a handful of components; a count beyond this is garbage.
  if (count > kMaxComponents)
    throw PluginError("'" + path + "' claims " + std::to_string(count) + " " + to_string(kind) +
                      " components (at most " + std::to_string(kMaxComponents) + ")");
  for (uint32_t i = 0; i < count; ++i) {
    ComponentInfo info{};
    info.kind = kind;
    info.descriptor = f.descriptor(plugin_factory, i);
    info.abi_version = v;
    info.library = library;
    info.*slot = f;
    info.factory = raw;
    if (info.descriptor == nullptr || info.descriptor->id == nullptr) continue;
    const std::string problem = descriptor_problem(*info.descriptor);
    if (!problem.empty())
      throw PluginError("'" + path + "' offers a " + to_string(kind) + " component (number " +
                        std::to_string(i) + ") whose descriptor cannot be quoted: " + problem);
    info.id = info.descriptor->id;
    found.push_back(info);
  }
}

// Whether two files hold the same bytes (the same plugin installed twice).
bool same_contents(const std::string& a, const std::string& b) {
  std::error_code ec1, ec2;
  if (fs::file_size(a, ec1) != fs::file_size(b, ec2) || ec1 || ec2) return false;
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  return std::equal(std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(fb), std::istreambuf_iterator<char>());
}

// Why the dynamic loader refuses `path` in its own words (dlerror), which the
// error code of the library loader reduces to an errno ("Bad file descriptor").
std::string dlopen_reason(const std::string& path, const std::string& fallback) {
  ::dlerror();
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle != nullptr) {
    ::dlclose(handle);
    return fallback;
  }
  const char* reason = ::dlerror();
  return reason != nullptr ? reason : fallback;
}

std::string canonical_path(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(path, ec);
  return ec ? path : p.string();
}

}  // namespace

// Long enough for any honest init; a probe that takes longer is killed.
constexpr std::chrono::milliseconds kProbeLimit{10'000};

PluginRegistry::PluginRegistry()
    : probe_cache_(std::make_unique<ProbeCache>(ProbeCache::default_file())) {}
PluginRegistry::~PluginRegistry() {
  // Components first (they point into the libraries), then the libraries in
  // reverse order of loading.
  components_.clear();
  while (!libraries_.empty()) libraries_.pop_back();
}

std::vector<std::string> PluginRegistry::default_search_path() {
  std::vector<std::string> path;
  if (const char* env = std::getenv("MONOHYDRA_PLUGIN_PATH"); env != nullptr) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':'))
      if (!item.empty()) path.push_back(item);
  }
  std::error_code ec;
  // The engine in a shared library (the embedding API's, in <prefix>/lib):
  // the plugins installed beside it come first, found from the library's own
  // location, so a program that embeds it needs no environment.
  const fs::path program = boost::dll::program_location(ec);
  std::error_code lib_ec;
  const fs::path engine = boost::dll::this_line_location(lib_ec);
  if (!lib_ec && (ec || engine != program))
    path.push_back((engine.parent_path() / "monohydra" / "plugins").lexically_normal());
  if (!ec)
    path.push_back(
        (program.parent_path() / ".." / "lib" / "monohydra" / "plugins").lexically_normal());
  path.emplace_back(MONOHYDRA_PLUGIN_INSTALL_DIR);
  return path;
}

void PluginRegistry::load(const std::string& path) {
  try {
    load_library(path);
  } catch (const PluginError&) {
    probe_cache_->save();
    throw;
  }
  probe_cache_->save();
}

void PluginRegistry::load_library(const std::string& path) {
  const std::string canonical = canonical_path(path);
  for (const auto& lib : libraries_)
    if (lib->path == canonical || same_contents(lib->path, canonical)) return;

  // Nothing of the library runs in this process before a child survived it.
  std::optional<ProbeVerdict> verdict = probe_cache_->find(canonical);
  if (!verdict) {
    verdict = probe_library(canonical, kProbeLimit);
    probe_cache_->remember(canonical, *verdict);
  }
  if (!verdict->usable) throw PluginError("'" + path + "' " + verdict->reason);

  auto lib = std::make_unique<Library>();
  lib->path = canonical;
  boost::dll::fs::error_code ec;
  lib->library.load(canonical, boost::dll::load_mode::rtld_local | boost::dll::load_mode::rtld_now,
                    ec);
  if (ec)
    throw PluginError("'" + path + "' is not a loadable shared library: " +
                      dlopen_reason(canonical, ec.message()));
  if (!lib->library.has(MH_ENTRY_SYMBOL))
    throw PluginError("'" + path +
                      "' is not a monohydra plugin: it does not export the entry "
                      "symbol '" MH_ENTRY_SYMBOL "'");
  lib->entry = &lib->library.get<const mh_plugin_entry>(MH_ENTRY_SYMBOL);
  const mh_version v = lib->entry->abi_version;
  if (v.major != MH_ABI_VERSION_MAJOR) {
    const std::string got = std::to_string(v.major) + "." + std::to_string(v.minor);
    lib->entry = nullptr;  // never call into an incompatible library
    throw PluginError("'" + path + "' was built for monohydra ABI " + got +
                      ", this host speaks ABI " + std::to_string(MH_ABI_VERSION_MAJOR) + "." +
                      std::to_string(MH_ABI_VERSION_MINOR) +
                      " (major versions must match: rebuild the plugin against SDK " +
                      std::to_string(MH_ABI_VERSION_MAJOR) +
                      (v.major == 2 ? "; what changed since ABI 2 and how to port it: "
                                      "\"Migrating a 2.x plugin\" in docs/sdk.md)"
                                    : ")"));
  }
  if (lib->entry->init == nullptr || lib->entry->get_factory == nullptr) {
    lib->entry = nullptr;
    throw PluginError("'" + path + "' has an incomplete entry (init or get_factory is NULL)");
  }
  if (lib->entry->init(canonical.c_str()) == 0) {
    lib->entry = nullptr;
    throw PluginError("'" + path + "' failed to initialise (its init returned 0)");
  }

  std::vector<ComponentInfo> found;
  list_components(lib->entry->get_factory(MH_FORMULATION_FACTORY_ID), ComponentKind::formulation,
                  &ComponentInfo::formulation_factory, v, canonical, path, found);
  list_components(lib->entry->get_factory(MH_SUBSYSTEM_FACTORY_ID), ComponentKind::subsystem,
                  &ComponentInfo::subsystem_factory, v, canonical, path, found);
  list_components(lib->entry->get_factory(MH_INTEGRATOR_FACTORY_ID), ComponentKind::integrator,
                  &ComponentInfo::integrator_factory, v, canonical, path, found);
  libraries_.push_back(std::move(lib));
  components_.insert(components_.end(), found.begin(), found.end());
}

void PluginRegistry::scan(const std::vector<std::string>& folders) {
  for (const auto& folder : folders) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder, ec))
      if (e.path().extension() == ".so") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      try {
        load_library(f.string());
      } catch (const PluginError& err) {
        refusals_.emplace_back(err.what());
      }
    }
  }
  probe_cache_->save();
}

void PluginRegistry::choose(const std::string& id, const std::string& library) {
  choices_.emplace_back(id, canonical_path(library));
}

const ComponentInfo& PluginRegistry::find(ComponentKind kind, const std::string& id) const {
  std::string known;
  std::vector<const ComponentInfo*> offers;
  for (const auto& c : components_) {
    if (c.kind != kind) continue;
    if (c.id == id) offers.push_back(&c);
    known += (known.empty() ? "" : ", ") + c.id;
  }
  std::string from;  // every library that offers it
  for (const auto* c : offers) from += (from.empty() ? "'" : ", '") + c->library + "'";
  for (const auto& [chosen_id, library] : choices_) {
    if (chosen_id != id) continue;
    for (const auto* c : offers)
      if (c->library == library) return *c;
    throw PluginError(std::string(to_string(kind)) + " '" + id + "' is to come from '" + library +
                      "' (plugins: in the model file), which does not offer it" +
                      (from.empty() ? std::string() : " (offered by " + from + ")"));
  }
  if (offers.size() == 1) return *offers.front();
  if (offers.size() > 1)
    throw PluginError(std::string(to_string(kind)) + " '" + id + "' is offered by " +
                      std::to_string(offers.size()) + " libraries: " + from +
                      "; say which in the model file: plugins: {" + id + ": LIBRARY.so}");
  // A library that was refused may be the one meant: say which, and why.
  std::string refused;
  for (const auto& r : refusals_) refused += "; refused: " + r;
  throw PluginError("unknown " + std::string(to_string(kind)) + " '" + id + "' (found: " +
                    (known.empty() ? std::string("none; check the plugin search path") : known) +
                    refused + ")");
}

}  // namespace mh
