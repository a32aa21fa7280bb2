#include "measurement_stream.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "monohydra/core/input_error.hpp"

namespace mh::cli {

namespace {

// The whole of `text` as a finite number, or false.
bool finite_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno == 0 && std::isfinite(value);
}

std::string trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

}  // namespace

MeasurementStream::MeasurementStream(std::istream& in, std::vector<std::string> sensors,
                                     std::string label)
    : in_(in), sensors_(std::move(sensors)), label_(std::move(label)) {}

bool MeasurementStream::next(MeasurementLine& line) {
  std::string text;
  while (std::getline(in_, text))
    if (parse(text, line)) return true;
  return false;
}

bool MeasurementStream::parse(const std::string& raw, MeasurementLine& line) {
  ++number_;
  const std::string text = trimmed(raw);
  if (text.empty() || text[0] == '#') return false;
  const SourceMark mark{label_, static_cast<int>(number_), 0};
  std::vector<std::string> fields;
  for (size_t at = 0;;) {
    const size_t comma = text.find(',', at);
    fields.push_back(trimmed(text.substr(at, comma - at)));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  line.number = number_;
  if (!finite_number(fields[0], line.t))
    throw InputError(mark, "t", "a time in s first (t,NAME=VALUE,...), not '" + fields[0] + "'");
  if (!(line.t >= last_t_))
    throw InputError(mark, "t",
                     "times that do not go backwards: " + fields[0] + " after a line at " +
                         std::to_string(last_t_));
  last_t_ = line.t;
  line.readings = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(sensors_.size()), NAN);
  for (size_t f = 1; f < fields.size(); ++f) {
    const size_t eq = fields[f].find('=');
    if (eq == std::string::npos)
      throw InputError(mark, "field " + std::to_string(f + 1),
                       "NAME=VALUE, not '" + fields[f] + "'");
    const std::string name = trimmed(fields[f].substr(0, eq));
    const std::string value = trimmed(fields[f].substr(eq + 1));
    size_t s = 0;
    while (s < sensors_.size() && sensors_[s] != name) ++s;
    if (s == sensors_.size()) {
      std::string known;
      for (const std::string& n : sensors_) known += (known.empty() ? "" : ", ") + n;
      throw InputError(mark, name, "one of the model's sensors (" + known + ")");
    }
    double& reading = line.readings[static_cast<Eigen::Index>(s)];
    if (!std::isnan(reading)) throw InputError(mark, name, "one reading per sensor and line");
    if (value.empty()) continue;  // no sample, as an empty field of a CSV
    if (!finite_number(value, reading))
      throw InputError(mark, name, "a finite number, not '" + value + "'");
  }
  return true;
}

MeasurementQueue::MeasurementQueue(MeasurementStream& stream, int fd)
    : stream_(stream), fd_(fd), reader_([this] { read_lines(); }) {}

MeasurementQueue::~MeasurementQueue() {
  stop_ = true;
  reader_.join();
}

void MeasurementQueue::read_lines() {
  std::string pending;
  char buffer[4096];
  try {
    while (!stop_) {
      // What has come is read at once; only when nothing has does the
      // reader say it waits (a pop then returns without a line).
      pollfd p{fd_, POLLIN, 0};
      int ready = ::poll(&p, 1, 0);
      if (ready == 0) {
        mark_idle(true);
        ready = ::poll(&p, 1, 50);
        if (ready > 0) mark_idle(false);
      }
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) {
        if (ready < 0) break;
        continue;
      }
      const ssize_t got = ::read(fd_, buffer, sizeof(buffer));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) break;  // the end (or an error: the same to the filter)
      pending.append(buffer, static_cast<size_t>(got));
      for (size_t eol = pending.find('\n'); eol != std::string::npos; eol = pending.find('\n')) {
        MeasurementLine line;
        const bool taken = stream_.parse(pending.substr(0, eol), line);
        pending.erase(0, eol + 1);
        if (!taken) continue;
        const std::lock_guard<std::mutex> lock(mutex_);
        lines_.push_back(std::move(line));
        arrived_.notify_one();
      }
    }
    MeasurementLine line;
    if (!stop_ && !pending.empty() && stream_.parse(pending, line)) {
      const std::lock_guard<std::mutex> lock(mutex_);
      lines_.push_back(std::move(line));
    }
  } catch (...) {
    const std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  arrived_.notify_one();
}

bool MeasurementQueue::pop_wait(MeasurementLine& line) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait(lock, [this] { return !lines_.empty() || done_; });
  if (lines_.empty()) return false;
  line = std::move(lines_.front());
  lines_.pop_front();
  return true;
}

void MeasurementQueue::mark_idle(bool idle) {
  const std::lock_guard<std::mutex> lock(mutex_);
  idle_ = idle;
  arrived_.notify_one();
}

bool MeasurementQueue::pop(MeasurementLine& line) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait(lock, [this] { return !lines_.empty() || done_ || idle_; });
  if (lines_.empty()) return false;
  line = std::move(lines_.front());
  lines_.pop_front();
  return true;
}

bool MeasurementQueue::ended() {
  const std::lock_guard<std::mutex> lock(mutex_);
  return done_ && lines_.empty();
}

void MeasurementQueue::rethrow() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (error_) std::rethrow_exception(error_);
}

}  // namespace mh::cli
