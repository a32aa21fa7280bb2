#include "progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace mh::cli::sweep {

Progress::Progress(std::size_t total, std::size_t already_done)
    : total_(total),
      done_(already_done),
      tty_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {
  if (already_done > 0)
    std::fprintf(stderr, "sweep: %zu of %zu cases have a row already; running the other %zu\n",
                 already_done, total, total - already_done);
}

std::string Progress::duration_text(double seconds) {
  char buf[64];
  const long s = std::lround(seconds);
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%ld s", s);
  }
  return buf;
}

void Progress::case_done(const std::string& status) {
  ++done_;
  ++done_now_;
  if (status != "ok") ++not_ok_;
  draw(false);
}

void Progress::note(const std::string& text) {
  if (tty_) std::fputs("\r\033[K", stderr);
  std::fprintf(stderr, "sweep: %s\n", text.c_str());
}

void Progress::draw(bool final) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction =
      total_ == 0 ? 1.0 : static_cast<double>(done_) / static_cast<double>(total_);
  const int decile = static_cast<int>(fraction * 10.0);
  if (!tty_ && !final && decile == last_decile_) return;
  last_decile_ = decile;
  std::string left = "?";
  if (done_now_ > 0)
    left = duration_text(elapsed / static_cast<double>(done_now_) *
                         static_cast<double>(total_ - done_));
  const int width = 30;
  const int filled = static_cast<int>(fraction * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "%s[%s] %zu/%zu cases, %zu not ok, %s spent, %s left%s",
               tty_ ? "\r\033[K" : "", bar.c_str(), done_, total_, not_ok_,
               duration_text(elapsed).c_str(), final ? "0 s" : left.c_str(), tty_ ? "" : "\n");
  std::fflush(stderr);
}

void Progress::finish() {
  if (tty_) {
    draw(true);
    std::fputc('\n', stderr);
  } else if (last_decile_ != 10) {
    draw(true);
  }
}

}  // namespace mh::cli::sweep
