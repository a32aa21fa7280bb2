// The tests' FMU importer, written against the standard's calling sequence
// (FMI 3.0, 2.3 and 4.2; FMI 2.0, 2.1 and 4.2) and nothing of monohydra's:
// it unzips an .fmu, reads its modelDescription.xml, loads
// binaries/x86_64-linux/<modelIdentifier>.so and resolves every function the
// standard requires by name, as another tool would.
#pragma once

#include <filesystem>
#include <map>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "monohydra/fmi/fmi2.h"
#include "monohydra/fmi/fmi3.h"

namespace mh::test {

// The archive unpacked into `dir`; throws std::runtime_error with libzip's reason.
void unzip(const std::filesystem::path& fmu, const std::filesystem::path& dir);

struct Unpacked {
  std::filesystem::path dir;  // the unpacked FMU
  pugi::xml_document description;
  std::string model_identifier, token;
  std::map<std::string, std::uint32_t> vr;  // value references by variable name
};

// Unpacks `fmu` into `dir` and reads its description (either version).
Unpacked unpack(const std::filesystem::path& fmu, const std::filesystem::path& dir);

// The FMI 3.0 functions of a loaded binary (every one the standard lists).
struct Fmi3Functions {
  void* handle = nullptr;
  std::vector<std::string> missing;  // functions the binary does not export
#define MH_FMI3_FN(name) name##TYPE* name = nullptr;
#include "fmi3_function_list.inc"
#undef MH_FMI3_FN
};

struct Fmi2Functions {
  void* handle = nullptr;
  std::vector<std::string> missing;
#define MH_FMI2_FN(name) name##TYPE* name = nullptr;
#include "fmi2_function_list.inc"
#undef MH_FMI2_FN
};

Fmi3Functions load_fmi3(const Unpacked& fmu);
Fmi2Functions load_fmi2(const Unpacked& fmu);
void unload(void* handle);

// What the FMU logged through the callback, for assertions on messages.
struct LogRecord {
  std::vector<std::pair<int, std::string>> messages;  // (status, "category: message")
  std::string all() const;
};
void log_fmi3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
              fmi3String message);
void log_fmi2(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
              fmi2String category, fmi2String message, ...);

}  // namespace mh::test
