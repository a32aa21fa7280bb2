// A model file's text, read with the checks load_model_file makes (it
// exists, is a regular text file below 64 MiB, ends with a line break), for
// hosts that change values in the text before the parser reads it
// (run --set, the embedding API's settings).
#pragma once

#include <string>

namespace mh {

// Throws InputError naming the file.
std::string read_model_text(const std::string& path);

}  // namespace mh
