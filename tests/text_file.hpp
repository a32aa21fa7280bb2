// A file's whole contents, bytes as they are ("" when it cannot be read):
// what a test compares a written file or a header with.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mh::test {

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mh::test
