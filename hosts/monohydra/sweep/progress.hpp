// The study's progress on stderr: cases done of all, failures, time spent
// and an estimate of the time left (the mean time per case finished in this
// session, times the cases left, over the workers). On a terminal one line
// redrawn; otherwise a line every 10 %.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace mh::cli::sweep {

class Progress {
 public:
  Progress(std::size_t total, std::size_t already_done);
  void case_done(const std::string& status);
  void note(const std::string& text);  // a line of its own (a reference run's end)
  void finish();

  // "1 h 02 min", "3 min 20 s", "12 s".
  static std::string duration_text(double seconds);

 private:
  void draw(bool final);

  std::size_t total_, done_, done_now_ = 0, not_ok_ = 0;
  int last_decile_ = -1;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mh::cli::sweep
