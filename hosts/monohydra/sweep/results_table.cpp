#include "results_table.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace mh::cli::sweep {
namespace {

std::string optional_number(const std::optional<double>& v) {
  return v ? number_text(*v) : std::string();
}

std::string timing(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", seconds);
  return buf;
}

void write_all(int fd, const std::string& text, const std::string& path) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

// Writes `text` to `path` through a new file renamed over it: a reader (or a
// resumed study) sees the old file or the new one, never half of one.
void replace_file(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write '" + tmp + "': " + std::strerror(errno));
  write_all(fd, text, tmp);
  ::fdatasync(fd);
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename '" + tmp + "': " + std::strerror(errno));
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::vector<std::string> table_columns(const Study& study) {
  std::vector<std::string> cols = {"case", "model"};
  for (const auto& p : varied_paths(study)) cols.push_back(p);
  for (const char* c : {"status", "reason", "t_reached"}) cols.emplace_back(c);
  for (const auto& m : study.metrics) cols.push_back(m.header);
  for (const auto& c : kTimingColumns) cols.push_back(c);
  return cols;
}

std::string row_prefix(const Study& study, const Case& c) {
  std::string row = std::to_string(c.index) + "," + csv_field(study.models[c.model].name);
  for (const auto& [path, value] : c.values)
    row += "," + csv_field(value && value.IsScalar() ? value.Scalar() : std::string());
  return row + ",";
}

std::string format_row(const Study& study, const Case& c, const CaseOutcome& outcome) {
  std::string row = row_prefix(study, c) + csv_field(outcome.status) + "," +
                    csv_field(outcome.reason) + "," + optional_number(outcome.t_reached);
  for (std::size_t i = 0; i < study.metrics.size(); ++i)
    row += "," + (i < outcome.metrics.size() ? optional_number(outcome.metrics[i]) : "");
  return row + "," + timing(outcome.cpu_s) + "," + timing(outcome.wall_s) + "\n";
}

ResultsTable::ResultsTable(const std::string& dir, const Study& study,
                           const std::vector<Case>& cases)
    : path_((fs::path(dir) / "results.csv").string()) {
  for (const auto& c : table_columns(study)) header_ += (header_.empty() ? "" : ",") + c;
  header_ += "\n";
  std::error_code ec;
  if (!fs::exists(path_, ec)) {
    replace_file(path_, header_);
  } else {
    std::ifstream in(path_, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // A torn last line (only a machine that stopped can leave one) is no row.
    const std::size_t whole = text.rfind('\n');
    const std::size_t keep = whole == std::string::npos ? 0 : whole + 1;
    if (keep < text.size()) {
      fs::resize_file(path_, keep, ec);
      text.resize(keep);
    }
    if (text.compare(0, header_.size(), header_) != 0)
      throw std::runtime_error("'" + path_ +
                               "' has other columns than this study's table: it belongs to "
                               "another study (choose another --out, or remove it)");
    std::istringstream lines(text.substr(header_.size()));
    std::string line;
    while (std::getline(lines, line)) {
      if (line.empty()) continue;
      int index = -1;
      try {
        index = std::stoi(line.substr(0, line.find(',')));
      } catch (const std::exception&) {
      }
      if (index < 0 || index >= static_cast<int>(cases.size()) ||
          line.compare(0, row_prefix(study, cases[static_cast<std::size_t>(index)]).size(),
                       row_prefix(study, cases[static_cast<std::size_t>(index)])) != 0)
        throw std::runtime_error("'" + path_ + "' holds the row '" + line.substr(0, 80) +
                                 "', which is not a case of this study (choose another --out, "
                                 "or remove it)");
      rows_[index] = line + "\n";
    }
  }
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  // Two studies appending to one table would run every case twice.
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error("'" + path_ +
                             "' is being written by another monohydra sweep with the same --out");
  }
}

ResultsTable::~ResultsTable() {
  if (fd_ >= 0) ::close(fd_);
}

void ResultsTable::append(int case_index, const std::string& row) {
  write_all(fd_, row, path_);  // one write of the whole line
  if (::fdatasync(fd_) != 0)
    throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  rows_[case_index] = row;
}

void ResultsTable::finish() {
  std::string text = header_;
  for (const auto& [index, row] : rows_) text += row;
  replace_file(path_, text);
  ::close(fd_);
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
}

}  // namespace mh::cli::sweep
