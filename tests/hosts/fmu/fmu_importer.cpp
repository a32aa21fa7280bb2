#include "fmu_importer.hpp"

#include <dlfcn.h>
#include <zip.h>

#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace mh::test {

void unzip(const fs::path& fmu, const fs::path& dir) {
  int error = 0;
  zip_t* archive = zip_open(fmu.c_str(), ZIP_RDONLY, &error);
  if (archive == nullptr) throw std::runtime_error("cannot open " + fmu.string() + " as a zip");
  const zip_int64_t n = zip_get_num_entries(archive, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(archive, static_cast<zip_uint64_t>(i), 0);
    const fs::path out = dir / name;
    if (std::string(name).back() == '/') {
      fs::create_directories(out);
      continue;
    }
    fs::create_directories(out.parent_path());
    zip_file_t* f = zip_fopen_index(archive, static_cast<zip_uint64_t>(i), 0);
    if (f == nullptr) {
      zip_close(archive);
      throw std::runtime_error(std::string("cannot read ") + name + " in " + fmu.string());
    }
    std::ofstream o(out, std::ios::binary);
    char buffer[65536];
    zip_int64_t got = 0;
    while ((got = zip_fread(f, buffer, sizeof(buffer))) > 0) o.write(buffer, got);
    zip_fclose(f);
  }
  zip_close(archive);
}

Unpacked unpack(const fs::path& fmu, const fs::path& dir) {
  Unpacked u;
  u.dir = dir;
  unzip(fmu, dir);
  const pugi::xml_parse_result parsed =
      u.description.load_file((dir / "modelDescription.xml").c_str());
  if (!parsed)
    throw std::runtime_error(std::string("modelDescription.xml: ") + parsed.description());
  const pugi::xml_node root = u.description.child("fmiModelDescription");
  const pugi::xml_node cs = root.child("CoSimulation");
  u.model_identifier = cs.attribute("modelIdentifier").value();
  const bool v3 = std::string(root.attribute("fmiVersion").value()) == "3.0";
  u.token = root.attribute(v3 ? "instantiationToken" : "guid").value();
  for (const pugi::xml_node v : root.child("ModelVariables").children())
    u.vr[v.attribute("name").value()] =
        static_cast<std::uint32_t>(v.attribute("valueReference").as_uint());
  return u;
}

namespace {

void* open_binary(const Unpacked& fmu) {
  const fs::path so = fmu.dir / "binaries" / "x86_64-linux" / (fmu.model_identifier + ".so");
  void* handle = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) throw std::runtime_error(std::string("dlopen: ") + dlerror());
  return handle;
}

}  // namespace

Fmi3Functions load_fmi3(const Unpacked& fmu) {
  Fmi3Functions f;
  f.handle = open_binary(fmu);
#define MH_FMI3_FN(name)                                          \
  f.name = reinterpret_cast<name##TYPE*>(dlsym(f.handle, #name)); \
  if (f.name == nullptr) f.missing.emplace_back(#name);
#include "fmi3_function_list.inc"
#undef MH_FMI3_FN
  return f;
}

Fmi2Functions load_fmi2(const Unpacked& fmu) {
  Fmi2Functions f;
  f.handle = open_binary(fmu);
#define MH_FMI2_FN(name)                                          \
  f.name = reinterpret_cast<name##TYPE*>(dlsym(f.handle, #name)); \
  if (f.name == nullptr) f.missing.emplace_back(#name);
#include "fmi2_function_list.inc"
#undef MH_FMI2_FN
  return f;
}

void unload(void* handle) {
  if (handle != nullptr) dlclose(handle);
}

std::string LogRecord::all() const {
  std::string text;
  for (const auto& [status, message] : messages) text += message + "\n";
  return text;
}

void log_fmi3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
              fmi3String message) {
  if (env == nullptr) return;
  static_cast<LogRecord*>(env)->messages.emplace_back(static_cast<int>(status),
                                                      std::string(category) + ": " + message);
}

void log_fmi2(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
              fmi2String category, fmi2String message, ...) {
  (void)instance;
  if (env == nullptr) return;
  char text[8192];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof(text), message, args);
  va_end(args);
  static_cast<LogRecord*>(env)->messages.emplace_back(static_cast<int>(status),
                                                      std::string(category) + ": " + text);
}

}  // namespace mh::test
