// Where an FMU's resources/ folder is, from what the importer passes: FMI 3.0
// gives a path (with a trailing separator), FMI 2.0 a URI ("file:///a/b",
// "file:/a/b", percent-encoded).
#pragma once

#include <string>

namespace mh::fmu {

// The folder of `resource_path` (a path or a file URI) with a trailing '/'.
// Throws std::runtime_error for a URI that is not a local file.
std::string directory_of_resources(const std::string& resource_path);

}  // namespace mh::fmu
