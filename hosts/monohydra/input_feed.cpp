#include "input_feed.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "monohydra/core/input_error.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh::cli {
namespace {

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// The whole text as a finite number, or false.
bool parse_finite(const std::string& text, double& out) {
  const std::string t = trimmed(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && errno == 0 && std::isfinite(out);
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string known_inputs(const Simulation& sim) {
  std::string known;
  for (const InputSpec& in : sim.inputs()) known += (known.empty() ? "" : ", ") + in.name;
  return known.empty() ? "the model declares none" : known;
}

}  // namespace

InputFeed InputFeed::from_csv(const std::string& path, const Simulation& sim) {
  std::ifstream in(path);
  if (!in) throw InputError(SourceMark{path, 0, 0}, "--inputs", "a readable CSV file");
  InputFeed feed;
  std::string line;
  int number = 0;
  std::vector<int> columns;  // input index per column after t
  double last_t = -HUGE_VAL;
  while (std::getline(in, line)) {
    ++number;
    if (trimmed(line).empty()) continue;
    const std::vector<std::string> c = cells(line);
    if (columns.empty() && number == 1) {
      if (c.empty() || trimmed(c[0]) != "t")
        throw InputError(SourceMark{path, number, 1}, "header",
                         "a header 't,NAME,...' whose first column is t, got '" + line + "'");
      for (size_t j = 1; j < c.size(); ++j) {
        const std::string name = trimmed(c[j]);
        const int k = sim.input_index(name);
        if (k < 0)
          throw InputError(
              SourceMark{path, number, 0}, "header column " + std::to_string(j + 1),
              "one of the model's inputs (" + known_inputs(sim) + "), got '" + name + "'");
        for (int other : columns)
          if (other == k)
            throw InputError(SourceMark{path, number, 0}, "header column " + std::to_string(j + 1),
                             "each input once, got '" + name + "' twice");
        columns.push_back(k);
      }
      if (columns.empty())
        throw InputError(SourceMark{path, number, 1}, "header", "at least one input after t");
      continue;
    }
    if (c.size() != columns.size() + 1)
      throw InputError(SourceMark{path, number, 0}, "row",
                       std::to_string(columns.size() + 1) + " cells as the header has, got " +
                           std::to_string(c.size()));
    Row row;
    if (!parse_finite(c[0], row.t) || row.t < last_t)
      throw InputError(SourceMark{path, number, 1}, "t",
                       "a finite time (s), not before the row above, got '" + c[0] + "'");
    last_t = row.t;
    for (size_t j = 0; j < columns.size(); ++j) {
      if (trimmed(c[j + 1]).empty()) continue;  // left as it is
      double v = 0.0;
      if (!parse_finite(c[j + 1], v))
        throw InputError(SourceMark{path, number, 0}, sim.inputs()[columns[j]].name,
                         "a finite number, got '" + c[j + 1] + "'");
      const std::string refusal = sim.input_refusal(columns[j], v);
      if (!refusal.empty())
        throw InputError(SourceMark{path, number, 0}, sim.inputs()[columns[j]].name, refusal);
      row.values.emplace_back(columns[j], v);
    }
    feed.rows_.push_back(std::move(row));
  }
  if (columns.empty())
    throw InputError(SourceMark{path, 0, 0}, "--inputs", "a header 't,NAME,...' and rows");
  return feed;
}

InputFeed InputFeed::from_stream(int fd) {
  InputFeed feed;
  feed.fd_ = fd;
  return feed;
}

void InputFeed::apply_line(Simulation& sim, const std::string& raw) {
  ++line_number_;
  const std::string line = trimmed(raw);
  if (line.empty() || line[0] == '#') return;
  const auto warn = [&](const std::string& why) {
    std::cerr << "monohydra: --inputs -: line " << line_number_ << ": " << why << "; ignored\n";
  };
  const size_t eq = line.find('=');
  if (eq == std::string::npos) return warn("expected name=value, got '" + line + "'");
  const std::string name = trimmed(line.substr(0, eq));
  const int k = sim.input_index(name);
  if (k < 0) return warn("no input '" + name + "' (the model's inputs: " + known_inputs(sim) + ")");
  double v = 0.0;
  if (!parse_finite(line.substr(eq + 1), v))
    return warn("expected a finite number for '" + name + "', got '" + line.substr(eq + 1) + "'");
  const std::string refusal = sim.input_refusal(k, v);
  if (!refusal.empty()) return warn(refusal);
  sim.set_input(k, v);
}

void InputFeed::apply(Simulation& sim) {
  // A row holds from its time: due at the step that starts there (half a
  // step of slack for times written with round-off).
  const double due = sim.time() + 0.5 * sim.settings().dt;
  for (; next_row_ < rows_.size() && rows_[next_row_].t < due; ++next_row_)
    for (const auto& [k, v] : rows_[next_row_].values) sim.set_input(k, v);
  if (fd_ < 0) return;
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0 || (p.revents & (POLLIN | POLLHUP)) == 0) break;
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) {  // end of the stream: what is left is its last line
      if (!pending_.empty()) apply_line(sim, pending_);
      pending_.clear();
      fd_ = -1;
      break;
    }
    pending_.append(buffer, static_cast<size_t>(n));
    for (size_t end = pending_.find('\n'); end != std::string::npos; end = pending_.find('\n')) {
      apply_line(sim, pending_.substr(0, end));
      pending_.erase(0, end + 1);
    }
  }
}

}  // namespace mh::cli
