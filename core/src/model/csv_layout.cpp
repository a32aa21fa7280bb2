#include "monohydra/core/csv_layout.hpp"

#include <cmath>

#include "monohydra/cpp/number_text.hpp"

namespace mh {
// Results are exact (the shortest text that reads back as the same double);
// messages short.
using monohydra::put_exact_number;
using monohydra::short_number;

void CsvLayout::all_columns(const Simulation& sim, bool real_time, std::vector<Column>& columns,
                            std::vector<std::string>& names) {
  const auto add = [&](Source s, int index, const std::string& name) {
    columns.push_back({s, index});
    names.push_back(name);
  };
  add(Source::time, 0, "t");
  for (size_t i = 0; i < sim.coordinate_names().size(); ++i)
    add(Source::coordinate, static_cast<int>(i), sim.coordinate_names()[i]);
  for (size_t i = 0; i < sim.state_names().size(); ++i)
    if (!sim.state_names()[i].empty())
      add(Source::state, static_cast<int>(i), sim.state_names()[i]);
  for (size_t i = 0; i < sim.output_names().size(); ++i)
    if (!sim.output_names()[i].empty())
      add(Source::output, static_cast<int>(i), sim.output_names()[i]);
  add(Source::ke, 0, "KE");
  add(Source::pe, 0, "PE");
  add(Source::work, 0, "W");
  add(Source::drift, 0, "drift");
  add(Source::phi, 0, "phi_norm");
  add(Source::iters, 0, "iters");
  if (real_time) {
    add(Source::late, 0, "late");
    add(Source::unc, 0, "unconverged");
  }
}

CsvLayout::CsvLayout(const Simulation& sim, bool real_time) {
  all_columns(sim, real_time, columns_, names_);
}

CsvLayout::CsvLayout(const Simulation& sim, const OutputSettings& output,
                     std::optional<double> interval, bool real_time) {
  std::vector<Column> all;
  std::vector<std::string> all_names;
  all_columns(sim, real_time, all, all_names);
  if (output.columns.empty()) {
    columns_ = all;
    names_ = all_names;
  }
  for (size_t i = 0; i < output.columns.size(); ++i) {
    const std::string& name = output.columns[i];
    size_t k = 0;
    while (k < all_names.size() && all_names[k] != name) ++k;
    if (k == all_names.size()) {
      std::string known;
      for (const auto& n : all_names) known += (known.empty() ? "" : ", ") + n;
      throw InputError(output.column_marks[i], "output.columns[" + std::to_string(i) + "]",
                       "unknown column '" + name + "' (this run writes: " + known + ")");
    }
    columns_.push_back(all[k]);
    names_.push_back(name);
  }
  const double dt = sim.settings().dt;
  const double every = interval.value_or(output.interval);
  if (every > 0.0) {
    const std::string field = interval ? "--output-interval" : "output.interval";
    const SourceMark mark = interval ? SourceMark{} : output.interval_mark;
    const double steps = every / dt;
    const double whole = std::round(steps);
    // A row lands on each multiple of the interval only when it is a whole
    // number of steps (t = k dt exactly).
    if (!(whole >= 1.0) || std::abs(steps - whole) > 1e-9 * whole || whole > 1e15)
      throw InputError(mark, field,
                       "expected a whole multiple of the time step dt = " + short_number(dt) +
                           " s, got " + short_number(every) + " s (" + short_number(steps) +
                           " steps)");
    every_ = static_cast<long>(whole);
  }
}

void CsvLayout::header(std::ostream& out) const {
  for (size_t i = 0; i < names_.size(); ++i) {
    if (i > 0) out << ',';
    out << names_[i];
  }
  out << '\n';
}

double CsvLayout::value(const Column& c, const Simulation& sim, const RealTimeRow& rt) {
  switch (c.source) {
    case Source::time:
      return sim.time();
    case Source::coordinate:
      return sim.z()[c.index];
    case Source::state:
      return sim.states()[c.index];
    case Source::output:
      return sim.outputs()[c.index];
    case Source::ke:
      return sim.kinetic_energy();
    case Source::pe:
      return sim.potential_energy();
    case Source::work:
      return sim.work();
    case Source::drift:
      return sim.drift();
    case Source::phi:
      return sim.phi_norm();
    case Source::iters:
      return sim.last_step().iterations;
    case Source::late:
      return rt.late;
    case Source::unc:
      return rt.unconverged;
  }
  return 0.0;
}

void CsvLayout::row(std::ostream& out, const Simulation& sim, const RealTimeRow& rt) const {
  bool first = true;
  for (const Column& c : columns_) {
    if (!first) out << ',';
    first = false;
    if (c.source == Source::iters)
      out << sim.last_step().iterations;  // a count, written as one
    else
      put_exact_number(out, value(c, sim, rt));
  }
  out << '\n';
}

void CsvLayout::values(const Simulation& sim, double* out, const RealTimeRow& rt) const {
  for (const Column& c : columns_) *out++ = value(c, sim, rt);
}

}  // namespace mh
