// Inputs set from outside a `run` (--inputs): a time series read from a CSV
// file before the run, or lines `name=value` read from standard input while
// it runs (an operator's process feeding a --real-time run). Either sets the
// model's inputs (inputs:) between two steps through Simulation::set_input,
// as the embedding API's mhs_set does: a change is a jump at that time.
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/simulation.hpp"

namespace mh::cli {

class InputFeed {
 public:
  // FILE.csv: a header `t,NAME,...` naming inputs of the model, then rows of
  // a time (s, non-decreasing) and values (an empty cell leaves its input
  // as it is); each row holds from its time on. Throws InputError (file,
  // line, column, what was expected) for anything else, before the run.
  static InputFeed from_csv(const std::string& path, const Simulation& sim);
  // Lines `name=value` from the file descriptor `fd` (standard input), read
  // without waiting: each line is applied before the next step. A bad line is
  // reported on standard error with its number and skipped.
  static InputFeed from_stream(int fd);

  // Before the step from sim.time(): sets what is due (CSV rows whose time
  // has come; stream lines read so far).
  void apply(Simulation& sim);

 private:
  struct Row {
    double t = 0.0;
    std::vector<std::pair<int, double>> values;  // (input index, value)
  };
  void apply_line(Simulation& sim, const std::string& line);

  std::vector<Row> rows_;  // from_csv
  size_t next_row_ = 0;
  int fd_ = -1;          // from_stream; -1 when closed or none
  std::string pending_;  // a stream's bytes after its last full line
  long line_number_ = 0;
};

}  // namespace mh::cli
