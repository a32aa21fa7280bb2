// Readings that arrive while `estimate` runs (--measurements -): one line
// per sampling time, `t,NAME=VALUE,NAME=VALUE,...`, the names the model's
// sensors', each line's sensors those that took a sample then (the others
// stay absent, as an empty field of a CSV). A digital twin's feed: the
// filter steps up to each line's time as it arrives and writes its estimate
// at once.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <istream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace mh::cli {

struct MeasurementLine {
  long number = 0;           // 1-based, in the stream
  double t = 0.0;            // s
  Eigen::VectorXd readings;  // one per sensor, NaN where the line has none
};

class MeasurementStream {
 public:
  // `sensors`: the names a line may use, in the readings' order; `label`
  // names the stream in messages ("standard input").
  MeasurementStream(std::istream& in, std::vector<std::string> sensors, std::string label);

  // The next line (blank lines and lines starting with # skipped); false at
  // the end of the stream. Throws InputError naming the stream, the line
  // and the field: a time that is not a finite number or that goes
  // backwards, a pair without '=', a name that is not a sensor or that the
  // line gives twice, a value that is not a finite number.
  bool next(MeasurementLine& line);
  // The same of one line's text (its number counted): false for a blank
  // line or a comment.
  bool parse(const std::string& text, MeasurementLine& line);

 private:
  std::istream& in_;
  std::vector<std::string> sensors_;
  std::string label_;
  long number_ = 0;
  double last_t_ = -HUGE_VAL;
};

// A stream's lines read by a thread of their own from a file descriptor,
// so that a paced filter (estimate --real-time) never waits for one to
// arrive: it takes what has come. A line that has come but is not yet
// parsed counts as come (a pop waits for the reader, which a loaded
// machine may not have run), so that a file's lines, all there from the
// start, are each taken at their own step. The thread polls, so that it
// stops with its owner even while nothing arrives.
class MeasurementQueue {
 public:
  MeasurementQueue(MeasurementStream& stream, int fd);
  ~MeasurementQueue();
  MeasurementQueue(const MeasurementQueue&) = delete;
  MeasurementQueue& operator=(const MeasurementQueue&) = delete;

  // The next line, waiting for it; false once the stream has ended.
  bool pop_wait(MeasurementLine& line);
  // The next line if one has come to the input; false if the reader
  // waits for one (nothing unread there).
  bool pop(MeasurementLine& line);
  // The stream has ended and every line is taken.
  bool ended();
  // The stream's error (a bad line; InputError), if it stopped on one.
  void rethrow();

 private:
  void read_lines();
  void mark_idle(bool idle);

  MeasurementStream& stream_;
  int fd_;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<MeasurementLine> lines_;
  bool done_ = false;
  bool idle_ = false;  // the reader waits for input: nothing unread
  std::exception_ptr error_;
  std::atomic<bool> stop_{false};
  std::thread reader_;
};

}  // namespace mh::cli
