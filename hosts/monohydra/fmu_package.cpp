#include "fmu_package.hpp"

#include <zip.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace mh::cli {

namespace {

// The libraries of the base system: every importer has them loaded already.
bool is_system_library(const std::string& soname) {
  static const std::array<const char*, 14> base = {
      "linux-vdso.so", "ld-linux",   "libc.so",      "libm.so",     "libdl.so",
      "libpthread.so", "librt.so",   "libstdc++.so", "libgcc_s.so", "libasan.so",
      "libubsan.so",   "liblsan.so", "libtsan.so",   "libresolv.so"};
  return std::any_of(base.begin(), base.end(),
                     [&](const char* b) { return soname.rfind(b, 0) == 0; });
}

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::vector<std::string> bundled_libraries(const std::string& binary) {
  const std::string command = "ldd " + shell_quoted(binary) + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) throw std::runtime_error("cannot run ldd on " + binary);
  std::string text;
  std::array<char, 512> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe.get()) != nullptr) text += buffer.data();
  const int status = pclose(pipe.release());
  if (status != 0) throw std::runtime_error("ldd " + binary + " failed: " + text);
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string soname, arrow, path;
    words >> soname >> arrow >> path;
    if (arrow != "=>" || is_system_library(soname)) continue;
    if (path == "not")
      throw std::runtime_error(binary + " needs " + soname + ", which is not found on this system");
    out.push_back(path);
  }
  return out;
}

void write_zip(const std::string& dir, const std::string& zip_path) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  int error = 0;
  zip_t* archive = zip_open(zip_path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (archive == nullptr) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, error);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw std::runtime_error("cannot write " + zip_path + ": " + why);
  }
  auto fail = [&](const std::string& what) {
    const std::string why = zip_error_strerror(zip_get_error(archive));
    zip_discard(archive);
    throw std::runtime_error("cannot write " + zip_path + ": " + what + ": " + why);
  };
  for (const fs::path& f : files) {
    const std::string name = fs::relative(f, dir).generic_string();
    zip_source_t* source = zip_source_file(archive, f.c_str(), 0, -1);
    if (source == nullptr) fail(f.string());
    const zip_int64_t index = zip_file_add(archive, name.c_str(), source, ZIP_FL_ENC_UTF_8);
    if (index < 0) {
      zip_source_free(source);
      fail(name);
    }
    if (zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 0) != 0)
      fail(name);
  }
  if (zip_close(archive) != 0) fail("closing");
}

std::string model_identifier_of(const std::string& name) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) != 0 ? c : '_';
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id.front())) != 0) id = "_" + id;
  return id;
}

}  // namespace mh::cli
