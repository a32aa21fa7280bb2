#include "cli_support.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>

namespace mh::cli {

std::optional<double> parse_number(const std::string& flag, const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  std::cerr << "monohydra: " << flag << " expects a number, got '" << text << "'\n";
  return std::nullopt;
}

void log_to_stderr(mh_log_level level, const std::string& source, const std::string& msg) {
  if (level < MH_LOG_WARNING) return;
  std::cerr << (level >= MH_LOG_ERROR ? "error: " : "warning: ") << source << ": " << msg << '\n';
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

}  // namespace mh::cli
