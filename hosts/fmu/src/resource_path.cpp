#include "resource_path.hpp"

#include <stdexcept>

namespace mh::fmu {

namespace {

int hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string directory_of_resources(const std::string& resource_path) {
  std::string path = resource_path;
  if (path.rfind("file:", 0) == 0) {
    std::string rest = path.substr(5);
    if (rest.rfind("//", 0) == 0) {
      rest = rest.substr(2);
      const std::size_t slash = rest.find('/');
      const std::string host = rest.substr(0, slash);
      if (!host.empty() && host != "localhost")
        throw std::runtime_error("the resource location '" + resource_path +
                                 "' is on another host: it must be a local file");
      rest = slash == std::string::npos ? "/" : rest.substr(slash);
    }
    path.clear();
    for (std::size_t i = 0; i < rest.size(); ++i) {
      if (rest[i] == '%' && i + 2 < rest.size() && hex(rest[i + 1]) >= 0 && hex(rest[i + 2]) >= 0) {
        path += static_cast<char>(hex(rest[i + 1]) * 16 + hex(rest[i + 2]));
        i += 2;
      } else {
        path += rest[i];
      }
    }
  } else if (path.find("://") != std::string::npos) {
    throw std::runtime_error("the resource location '" + resource_path +
                             "' is not a path nor a file URI");
  }
  if (path.empty()) throw std::runtime_error("the resource location is empty");
  if (path.back() != '/') path += '/';
  return path;
}

}  // namespace mh::fmu
