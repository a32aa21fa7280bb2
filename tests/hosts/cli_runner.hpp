// What the command-line tests share: running the built monohydra as a user
// does, a scratch folder per test process, and reading the CSVs it writes.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "build_paths.hpp"
#include "text_file.hpp"

namespace mh::test {

struct CliResult {
  int code = -1;
  std::string output;  // stdout and stderr
};

// Runs `monohydra ARGS` through the shell with plugins from the build tree
// only; `env` (e.g. "VAR=value ") and `cwd` go before it.
inline CliResult run_cli(const std::string& args, const std::string& env = "",
                         const std::string& cwd = "") {
  std::string cmd;
  if (!cwd.empty()) cmd = "cd '" + cwd + "' && ";
  cmd += "MONOHYDRA_PLUGIN_PATH= " + env + mh::test::paths::executable + std::string(" ") + args +
         " 2>&1";
  CliResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof(buf), pipe)) > 0) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Exit code and output of a shell command.
inline CliResult run_shell(const std::string& cmd) {
  CliResult r;
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof(buf), pipe)) > 0) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline bool have_program(const std::string& name) {
  return run_shell("command -v " + name + " >/dev/null").code == 0;
}

inline std::string shipped_model(const std::string& name) {
  return std::string(mh::test::paths::source_dir) + "/models/" + name;
}

// This test process's scratch folder; removed at exit when every test
// passed, kept for a look when one failed.
inline std::filesystem::path scratch_root() {
  return std::filesystem::temp_directory_path() / ("monohydra-test-" + std::to_string(::getpid()));
}
struct ScratchCleanup {
  // GoogleTest's singleton made first, so that it is destroyed after this
  // (statics die in the reverse order of their construction): asking a
  // destroyed one whether the tests passed is undefined (clang's ASan stops there).
  ScratchCleanup() { ::testing::UnitTest::GetInstance(); }
  ScratchCleanup(const ScratchCleanup&) = delete;
  ScratchCleanup& operator=(const ScratchCleanup&) = delete;
  ~ScratchCleanup() {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ec;
    std::filesystem::remove_all(scratch_root(), ec);
  }
};
inline const ScratchCleanup scratch_cleanup;

// A fresh folder for one test (removed first if a previous run left it).
inline std::filesystem::path scratch_dir(const std::string& name) {
  auto dir = scratch_root() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A CSV with a header row, by column name.
struct Csv {
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> columns;
  size_t rows = 0;
  const std::vector<double>& operator[](const std::string& name) const { return columns.at(name); }
};

inline Csv read_csv(const std::filesystem::path& p) {
  Csv csv;
  std::ifstream in(p);
  std::string line;
  if (!std::getline(in, line)) return csv;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) csv.header.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    size_t c = 0;
    for (std::string cell; std::getline(ss, cell, ',') && c < csv.header.size(); ++c)
      csv.columns[csv.header[c]].push_back(std::stod(cell));
    ++csv.rows;
  }
  return csv;
}

}  // namespace mh::test
