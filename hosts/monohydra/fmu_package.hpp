// The parts of writing an FMU that are files: the folder an FMU is staged
// in, the shared libraries its binary needs copied beside it, and the zip
// archive an .fmu is (FMI 3.0, 2.5: a zip file with modelDescription.xml,
// binaries/<platform>/ and resources/ at its root).
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

// The libraries `binary` loads (ldd's list), without those every Linux
// system has (the C and C++ runtime, the dynamic loader, the sanitizers'
// runtimes), which would clash with the importer's own. Throws
// std::runtime_error when ldd fails or a library is not found.
std::vector<std::string> bundled_libraries(const std::string& binary);

// Writes the folder `dir` (its files, recursively, in sorted order, with
// their paths relative to it) as the zip archive `zip_path`, deflated.
// Throws std::runtime_error with libzip's reason.
void write_zip(const std::string& dir, const std::string& zip_path);

// A C identifier from `name` (FMI's modelIdentifier is one): other
// characters become '_', a leading digit gets a '_' before it.
std::string model_identifier_of(const std::string& name);

}  // namespace mh::cli
