#include "measured_data.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <system_error>

#include "monohydra/core/input_error.hpp"
#include "monohydra/cpp/number_text.hpp"

namespace mh::cli {

namespace {

std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> out(1);
  for (const char c : line) {
    if (c == ',')
      out.emplace_back();
    else if (c != '\r')
      out.back() += c;
  }
  for (std::string& f : out) {  // surrounding blanks are not part of a value
    const size_t b = f.find_first_not_of(" \t");
    const size_t e = f.find_last_not_of(" \t");
    f = b == std::string::npos ? std::string() : f.substr(b, e - b + 1);
  }
  return out;
}

// The field as a finite double, or false.
bool finite_number(const std::string& text, double& value) {
  const char* first = text.data();
  const char* last = first + text.size();
  if (first != last && *first == '+') ++first;
  const auto [end, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && end == last && std::isfinite(value);
}

}  // namespace

size_t MeasuredData::count(size_t c) const {
  size_t n = 0;
  for (const double v : values[c])
    if (!std::isnan(v)) ++n;
  return n;
}

MeasuredData read_measured_data(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0, 0}, "--data", "a readable CSV file");
  MeasuredData data;
  data.path = path;
  std::string line;
  int number = 0;
  // The header: t, then names.
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") != std::string::npos) break;
  }
  if (number == 0 || line.find_first_not_of(" \t\r") == std::string::npos)
    throw InputError({path, 0, 0}, "header", "a first line `t,NAME,...`; the file is empty");
  const std::vector<std::string> header = fields_of(line);
  if (header.front() != "t")
    throw InputError({path, number, 1}, "header",
                     "`t` (the time, s) as the first column, not '" + header.front() + "'");
  std::set<std::string> seen;
  for (size_t c = 1; c < header.size(); ++c) {
    if (header[c].empty())
      throw InputError({path, number, static_cast<int>(c + 1)}, "header",
                       "a column name (column " + std::to_string(c + 1) + " is empty)");
    if (!seen.insert(header[c]).second)
      throw InputError({path, number, static_cast<int>(c + 1)}, header[c],
                       "one column of this name (it is named twice)");
    data.names.push_back(header[c]);
  }
  if (data.names.empty())
    throw InputError({path, number, 0}, "header", "at least one measured column after `t`");
  data.values.assign(data.names.size(), {});

  const double nan = std::numeric_limits<double>::quiet_NaN();
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> fields = fields_of(line);
    if (fields.size() != header.size())
      throw InputError({path, number, 0}, "row",
                       std::to_string(header.size()) + " fields as in the header, not " +
                           std::to_string(fields.size()));
    double t = 0.0;
    if (!finite_number(fields[0], t))
      throw InputError({path, number, 1}, "t", "a finite number (s), not '" + fields[0] + "'");
    if (!data.t.empty() && !(t > data.t.back()))
      throw InputError({path, number, 1}, "t",
                       "a time after the row before's " + monohydra::short_number(data.t.back()) +
                           " s (times increase strictly)");
    for (size_t c = 1; c < fields.size(); ++c) {
      double v = nan;
      if (!fields[c].empty()) {
        if (!finite_number(fields[c], v))
          throw InputError(
              {path, number, static_cast<int>(c + 1)}, header[c],
              "a finite number, or an empty field for a sample not taken, not '" + fields[c] + "'");
      }
      data.values[c - 1].push_back(v);
    }
    data.t.push_back(t);
  }
  if (data.t.empty())
    throw InputError({path, number, 0}, "data", "at least one row after the header");
  for (size_t c = 0; c < data.names.size(); ++c)
    if (data.count(c) == 0)
      throw InputError({path, 1, static_cast<int>(c + 2)}, data.names[c],
                       "at least one sample (the column is empty)");
  return data;
}

}  // namespace mh::cli
