#include "cli_support.hpp"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace mh::cli {

// strtod, not stod: stod throws for a subnormal like 1e-320 and for 1e400,
// which then read as "not a number"; both are numbers that the settings
// check refuses with their accepted range.
std::optional<ExplicitStabilityPolicy> parse_stability_option(const std::string& text) {
  ExplicitStabilityPolicy policy{};
  if (parse_explicit_stability(text, policy)) return policy;
  std::cerr << "monohydra: --explicit-stability expects error, warn or off, got '" << text << "'\n";
  return std::nullopt;
}

std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

std::optional<double> parse_number(const std::string& flag, const std::string& text) {
  if (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())) == 0) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() + text.size()) return v;
  }
  std::cerr << "monohydra: " << flag << " expects a number, got '" << text << "'\n";
  return std::nullopt;
}

bool parse_limit(const std::string& flag, const std::string& text, RunLimits& limits) {
  const std::optional<double> v = parse_number(flag, text);
  if (!v) return false;
  if (!std::isfinite(*v) || !(*v >= 1.0)) {
    std::cerr << "monohydra: " << flag << " expects a finite number >= 1, got '" << text << "'\n";
    return false;
  }
  (flag == "--max-steps" ? limits.max_steps : limits.max_output_bytes) = *v;
  return true;
}

void drop_partial_last_line(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return;
  // Backwards in blocks from the end to the last '\n': the CSV may be GBs.
  std::ifstream in(path, std::ios::binary);
  std::uintmax_t end = size;
  char block[4096];
  while (end > 0) {
    const std::uintmax_t start = end > sizeof block ? end - sizeof block : 0;
    const auto n = static_cast<std::streamsize>(end - start);
    in.seekg(static_cast<std::streamoff>(start));
    if (!in.read(block, n)) return;
    for (std::streamsize i = n; i > 0; --i)
      if (block[i - 1] == '\n') {
        const std::uintmax_t keep = start + static_cast<std::uintmax_t>(i);
        if (keep < size) std::filesystem::resize_file(path, keep, ec);
        return;
      }
    end = start;
  }
  std::filesystem::resize_file(path, 0, ec);  // not one whole line
}

namespace {
mh_log_level log_threshold = MH_LOG_WARNING;
std::string started_as;
}  // namespace

void log_to_stderr(mh_log_level level, const std::string& source, const std::string& msg) {
  if (level < log_threshold) return;
  const char* tag = level >= MH_LOG_ERROR     ? "error: "
                    : level >= MH_LOG_WARNING ? "warning: "
                    : level >= MH_LOG_INFO    ? "info: "
                                              : "debug: ";
  std::cerr << tag << source << ": " << msg << '\n';
}

void set_log_threshold(mh_log_level level) {
  log_threshold = level;
}

std::optional<mh_log_level> parse_log_level(const std::string& text) {
  if (text == "error") return MH_LOG_ERROR;
  if (text == "warn" || text == "warning") return MH_LOG_WARNING;
  if (text == "info") return MH_LOG_INFO;
  if (text == "debug") return MH_LOG_DEBUG;
  return std::nullopt;
}

void set_command_line(int argc, const char* const* argv) {
  started_as.clear();
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool plain = !arg.empty() && arg.find_first_not_of(
                                           "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                           "0123456789-_./=,:+@%") == std::string::npos;
    std::string quoted = "'";
    for (const char ch : arg) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    started_as += (i == 0 ? "" : " ") + (plain ? arg : quoted + "'");
  }
}

const std::string& command_line() {
  return started_as;
}

ProgressBar::ProgressBar() : enabled(isatty(STDERR_FILENO) != 0) {}

void ProgressBar::operator()(double fraction) const {
  if (!enabled) return;
  const int width = 40;
  const int filled = static_cast<int>(fraction * width);
  std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(static_cast<size_t>(filled), '#').c_str(),
               std::string(static_cast<size_t>(width - filled), ' ').c_str(),
               static_cast<int>(std::lround(fraction * 100.0)));
  if (fraction >= 1.0) std::fputc('\n', stderr);
}

int with_output_written(int code) {
  errno = 0;
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout) != 0) {
    std::cerr << "monohydra: cannot write to standard output: "
              << (errno != 0 ? std::strerror(errno) : "write failed") << '\n';
    if (code == 0) code = 1;
  }
  return code;
}

}  // namespace mh::cli
