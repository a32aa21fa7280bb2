// Recorded signals for `monohydra fit` (docs/identification.md): a CSV file
// whose header is `t` and the names of result columns as `run` writes them,
// then one row per sampling time. Samples may come at any times and rates:
// an empty field is a sample that was not taken, so a 1 kHz encoder and a
// 100 Hz pressure transducer share one file.
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

struct MeasuredData {
  std::string path;
  std::vector<std::string> names;  // the columns after t, in the file's order
  std::vector<double> t;           // strictly increasing, s
  // values[c][i]: column c at t[i]; NaN where the field was empty.
  std::vector<std::vector<double>> values;
  // How many samples column c has.
  size_t count(size_t c) const;
};

// Throws InputError naming the file, the line and the column: no `t` first
// in the header, a column named twice or empty, a row with another number
// of fields, a field that is not a finite number (NaN and infinities
// included), a time that does not increase on the row before it, a column
// without any sample, a file without any row. A row without any sample is
// kept (its time still checked): nothing was taken then.
MeasuredData read_measured_data(const std::string& path);

}  // namespace mh::cli
