// The result rows a run writes: which columns, in which order, and at which
// steps. By default every column (t, z1..zN, named states and outputs, KE, PE,
// W, drift, phi_norm, iters) at every step; the model file's `output:` (or
// --output-interval) selects columns and writes rows at multiples of an
// interval only. Real-time runs add two columns of their own. Names are
// resolved here, once: writing a row looks nothing up.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/simulation.hpp"

namespace mh {

// What a real-time run adds to a row: how late the step's result came and
// how far from converged it was accepted.
struct RealTimeRow {
  double late = 0.0;         // s after the step's wall-clock deadline (0: in time)
  double unconverged = 0.0;  // max_i |dx_i| / tol_i of its last iteration (0: converged)
};

class CsvLayout {
 public:
  // Every column, every step.
  explicit CsvLayout(const Simulation& sim, bool real_time = false);
  // The model file's output settings for `sim`'s columns and time step;
  // `interval` (the command line's) overrides the file's. Throws InputError
  // naming an unknown column (with the names the run writes) or an interval
  // that is not a whole number of time steps.
  CsvLayout(const Simulation& sim, const OutputSettings& output, std::optional<double> interval,
            bool real_time = false);

  // Rows are written at the steps k with k % every_steps() == 0 (and t = 0).
  long every_steps() const { return every_; }
  const std::vector<std::string>& names() const { return names_; }
  void header(std::ostream& out) const;
  void row(std::ostream& out, const Simulation& sim, const RealTimeRow& rt = {}) const;
  // The same row as numbers, names().size() of them (the embedding API's rows).
  void values(const Simulation& sim, double* out, const RealTimeRow& rt = {}) const;

 private:
  enum class Source { time, coordinate, state, output, ke, pe, work, drift, phi, iters, late, unc };
  struct Column {
    Source source;
    int index;
  };
  static double value(const Column& c, const Simulation& sim, const RealTimeRow& rt);
  static void all_columns(const Simulation& sim, bool real_time, std::vector<Column>& columns,
                          std::vector<std::string>& names);
  std::vector<Column> columns_;
  std::vector<std::string> names_;
  long every_ = 1;
};

}  // namespace mh
