// monohydra fmu MODEL --out FILE.fmu: writes the model as an FMI 3.0 (or,
// with --fmi-version 2, FMI 2.0) Co-Simulation FMU (docs/fmi.md). The FMU
// carries the engine (the binary hosts/fmu builds, with the libraries it
// needs beside it), the model and the plugin libraries its components come
// from, so it runs where monohydra is not installed. Its modelDescription.xml
// is written by the packed binary itself from the packed model.
#include <dlfcn.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "build_tree.hpp"
#include "commands.hpp"
#include "fmu_describe.h"
#include "fmu_package.hpp"
#include "run_setup.hpp"
#include "subcommand_parser.hpp"

namespace fs = std::filesystem;

namespace mh::cli {

namespace {

// The FMU binary: installed beside the tool's lib/, else the build tree's.
fs::path fmu_binary() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (const char* relative : {MONOHYDRA_FMU_RELATIVE, "../lib/monohydra/fmu/monohydra-fmu.so"}) {
      fs::path p = (exe.parent_path() / relative).lexically_normal();
      if (fs::is_regular_file(p, ec)) return p;
    }
  }
  fs::path built = build_tree::fmu_binary;
  if (fs::is_regular_file(built, ec)) return built;
  throw std::runtime_error(std::string("the FMU binary monohydra-fmu.so is not installed (looked "
                                       "beside this program and in ") +
                           build_tree::fmu_binary + ")");
}

// A staging folder that removes itself.
struct StagingDir {
  fs::path path;
  StagingDir() {
    std::string pattern = (fs::temp_directory_path() / "monohydra-fmu-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot make a temporary folder in " +
                               fs::temp_directory_path().string());
    path = pattern;
  }
  ~StagingDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  StagingDir(const StagingDir&) = delete;
  StagingDir& operator=(const StagingDir&) = delete;
};

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

// The model as the FMU carries it: its plugins: map names, for each
// component the run uses, the copy in resources/plugins/ (so that a library
// offering the same id elsewhere on the importer's machine is not asked).
std::string packed_model_text(const std::string& model_path,
                              const std::vector<host::UsedComponent>& used) {
  YAML::Node root = YAML::LoadFile(model_path);
  root.remove("plugin_paths");
  YAML::Node plugins(YAML::NodeType::Map);
  for (const auto& u : used) plugins[u.id] = "plugins/" + fs::path(u.library).filename().string();
  root["plugins"] = plugins;
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  return "# The model of this FMU, as monohydra fmu packed it from " +
         fs::path(model_path).filename().string() + "\n" + out.c_str() + "\n";
}

std::string settings_text(const RunRequest& request) {
  std::string text = "# What monohydra fmu chose over the model file, as its flags do.\nsettings:";
  if (request.formulation.empty() && request.integrator.empty()) return text + " []\n";
  text += "\n";
  if (!request.formulation.empty())
    text += "  - {path: formulation, value: \"" + request.formulation + "\"}\n";
  if (!request.integrator.empty())
    text += "  - {path: integrator, value: \"" + request.integrator + "\"}\n";
  return text;
}

// The packed binary writes the description: the CLI never guesses the table.
void describe(const fs::path& binary, const fs::path& resources, int version,
              const std::string& identifier, const fs::path& xml) {
  void* handle = dlopen(binary.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) throw std::runtime_error(std::string("cannot load ") + dlerror());
  std::unique_ptr<void, int (*)(void*)> guard(handle, dlclose);
  auto* fn = reinterpret_cast<mh_fmu_describe_fn*>(dlsym(handle, "mh_fmu_describe"));
  if (fn == nullptr) throw std::runtime_error(binary.string() + " has no mh_fmu_describe");
  char message[4096] = {};
  const std::string tool = std::string("monohydra ") + MONOHYDRA_VERSION;
  if (fn(resources.c_str(), version, identifier.c_str(), tool.c_str(), xml.c_str(), message,
         sizeof(message)) != 0)
    throw std::runtime_error(message);
}

}  // namespace

int fmu(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "fmu",
      "Write MODEL.yaml as an FMI 3.0 Co-Simulation FMU (--fmi-version 2: FMI 2.0) that runs "
      "without monohydra installed: every CSV column an output, the model's inputs inputs, its "
      "numeric options parameters (docs/fmi.md).");
  CLI::App& app = *app_holder;
  std::vector<std::string> models;
  std::string out_path, version_text = "3", identifier;
  RunRequest request;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--out", out_path, "the FMU to write (FILE.fmu)");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  app.add_option("--fmi-version", version_text, "3 (default) or 2");
  app.add_option("--model-identifier", identifier,
                 "the binary's name (default: the model's name, as a C identifier)");
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (models.size() != 1) {
    std::cerr << "monohydra: fmu needs one model file\n";
    return 2;
  }
  if (out_path.empty()) {
    std::cerr << "monohydra: fmu needs --out FILE.fmu\n";
    return 2;
  }
  if (version_text != "3" && version_text != "2") {
    std::cerr << "monohydra: --fmi-version expects 3 or 2, got '" << version_text << "'\n";
    return 2;
  }
  if (!identifier.empty() && identifier != model_identifier_of(identifier)) {
    std::cerr << "monohydra: --model-identifier expects a C identifier (letters, digits, _), got '"
              << identifier << "'\n";
    return 2;
  }
  request.model_path = models.front();
  const auto prepared = prepare_run(request);  // the model's errors, with file and line
  if (!prepared) return 2;
  try {
    if (identifier.empty()) {
      const YAML::Node root = YAML::LoadFile(request.model_path);
      identifier = model_identifier_of(root["name"] ? root["name"].as<std::string>()
                                                    : fs::path(request.model_path).stem().string());
    }
    const fs::path binary = fmu_binary();
    StagingDir staging;
    const fs::path bin_dir = staging.path / "binaries" / "x86_64-linux";
    const fs::path resources = staging.path / "resources";
    fs::create_directories(bin_dir);
    fs::create_directories(resources / "plugins");
    std::set<std::string> libraries;
    for (const auto& u : prepared->used) libraries.insert(u.library);
    for (const std::string& lib : libraries)
      fs::copy_file(lib, resources / "plugins" / fs::path(lib).filename(),
                    fs::copy_options::overwrite_existing);
    write_text(resources / "model.yaml", packed_model_text(request.model_path, prepared->used));
    write_text(resources / "monohydra-fmu.yaml", settings_text(request));
    const fs::path packed_binary = bin_dir / (identifier + ".so");
    fs::copy_file(binary, packed_binary, fs::copy_options::overwrite_existing);
    for (const std::string& lib : bundled_libraries(binary))
      fs::copy_file(fs::canonical(lib), bin_dir / fs::path(lib).filename(),
                    fs::copy_options::overwrite_existing);
    describe(packed_binary, resources, version_text == "2" ? 2 : 3, identifier,
             staging.path / "modelDescription.xml");
    write_zip(staging.path.string(), out_path);
  } catch (const std::exception& e) {
    std::cerr << "monohydra: fmu: " << e.what() << '\n';
    return 1;
  }
  std::cerr << "wrote " << out_path << " (FMI " << version_text << ".0 Co-Simulation, model "
            << "identifier " << identifier << ")\n";
  return 0;
}

}  // namespace mh::cli
