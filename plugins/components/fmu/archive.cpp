#include "archive.hpp"

#include <zip.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace fmu {
namespace {

namespace fs = std::filesystem;

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};

// An entry's name is a relative path inside the archive: one that is
// absolute or climbs out with ".." would write outside the folder.
bool safe_entry(const std::string& name) {
  if (name.empty() || name.front() == '/' || name.find('\\') != std::string::npos) return false;
  for (const auto& part : fs::path(name))
    if (part == "..") return false;
  return true;
}

}  // namespace

UnpackedArchive::UnpackedArchive(const std::string& archive) {
  std::error_code ec;
  if (!fs::is_regular_file(archive, ec))
    throw std::runtime_error("it does not exist or is not a file");
  int error = 0;
  const std::unique_ptr<zip_t, ZipCloser> zip(zip_open(archive.c_str(), ZIP_RDONLY, &error));
  if (zip == nullptr) {
    zip_error_t reason;
    zip_error_init_with_code(&reason, error);
    const std::string why = zip_error_strerror(&reason);
    zip_error_fini(&reason);
    throw std::runtime_error("it is not a zip archive (libzip: " + why + ")");
  }
  const fs::path base = fs::temp_directory_path(ec) / "monohydra-fmu-XXXXXX";
  std::string pattern = (ec ? fs::path("/tmp/monohydra-fmu-XXXXXX") : base).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (mkdtemp(name.data()) == nullptr)
    throw std::runtime_error(std::string("cannot make a temporary folder to unpack it into: ") +
                             std::strerror(errno));
  folder_ = name.data();  // from here on the destructor removes it
  try {
    const zip_int64_t entries = zip_get_num_entries(zip.get(), 0);
    std::vector<char> buffer(1 << 16);
    for (zip_int64_t i = 0; i < entries; ++i) {
      const char* entry = zip_get_name(zip.get(), static_cast<zip_uint64_t>(i), 0);
      const std::string entry_name = entry != nullptr ? entry : "";
      if (!safe_entry(entry_name))
        throw std::runtime_error("it has an entry outside its folder: '" + entry_name + "'");
      const fs::path target = fs::path(folder_) / entry_name;
      if (entry_name.back() == '/') {
        fs::create_directories(target);
        continue;
      }
      fs::create_directories(target.parent_path());
      const std::unique_ptr<zip_file_t, ZipFileCloser> in(
          zip_fopen_index(zip.get(), static_cast<zip_uint64_t>(i), 0));
      std::ofstream out(target, std::ios::binary);
      if (in == nullptr || !out)
        throw std::runtime_error("its entry '" + entry_name + "' does not unpack");
      zip_int64_t got = 0;
      while ((got = zip_fread(in.get(), buffer.data(), buffer.size())) > 0)
        out.write(buffer.data(), static_cast<std::streamsize>(got));
      if (got < 0 || !out)
        throw std::runtime_error("its entry '" + entry_name + "' does not unpack");
    }
  } catch (...) {
    fs::remove_all(folder_, ec);
    folder_.clear();
    throw;
  }
}

void UnpackedArchive::keep_only_resources() {
  if (folder_.empty()) return;
  std::error_code ec;
  const fs::path resources = fs::path(folder_) / "resources";
  if (!fs::is_directory(resources, ec) || fs::is_empty(resources, ec)) {
    fs::remove_all(folder_, ec);  // a loaded binary stays mapped
    folder_.clear();
    return;
  }
  for (const auto& entry : fs::directory_iterator(folder_, ec))
    if (entry.path().filename() != "resources") fs::remove_all(entry.path(), ec);
}

UnpackedArchive::~UnpackedArchive() {
  if (folder_.empty()) return;
  std::error_code ec;
  fs::remove_all(folder_, ec);  // best effort: a temporary folder
}

}  // namespace fmu
