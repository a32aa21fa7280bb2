#include "comparison_table.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>

#include "declared_outputs.hpp"

namespace mh::cli {
namespace {

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}
std::string g4(double v) {
  return fmt("%.4g", v);
}
std::string e3(double v) {
  return fmt("%.3e", v);
}
std::string paper_number(const std::optional<double>& v) {
  return v ? fmt("%g", *v) : "-";
}

std::string status(const RunRecord& r) {
  if (!r.failed) return "ok";
  if (r.crashed_by != 0) return r.failure;  // "crashed (SIGSEGV) after t = 0.1 s"
  if (r.failure_time) return "FAILED at t = " + fmt("%g", *r.failure_time) + " s";
  return r.rows() == 0 ? "FAILED at setup" : "FAILED at start";
}

}  // namespace

TextTable comparison_table(const Comparison& c, const PaperNumbers* paper) {
  TextTable t;
  const RunRecord* ref = c.reference_run();
  t.title = c.name + " (" + c.model_path + ")";
  if (ref != nullptr)
    t.title += ", dt = " + fmt("%g", ref->dt) + " s, t = 0 .. " + fmt("%g", ref->t_end) + " s";

  t.header.emplace_back("quantity");
  for (const auto& r : c.runs) {
    t.header.push_back(r.label);
    if (paper != nullptr) t.header.emplace_back("paper");
  }

  // One row: our cell per run (ours(i)) and the paper's beside it (theirs(formulation)).
  auto add_row = [&](const std::string& label, const auto& ours, const auto& theirs) {
    std::vector<std::string> cells{label};
    for (size_t i = 0; i < c.runs.size(); ++i) {
      cells.push_back(ours(i));
      if (paper != nullptr) {
        const std::string p = theirs(c.runs[i]);
        cells.push_back(p.empty() ? "-" : p);
      }
    }
    t.rows.push_back(std::move(cells));
  };
  auto none = [](const RunRecord&) { return std::string("-"); };
  auto has_rows = [&c](size_t i) { return c.runs[i].rows() > 0; };
  auto metric = [&](auto get) {
    return [&c, has_rows, get](size_t i) {
      return has_rows(i) ? get(c.metrics[i]) : std::string("-");
    };
  };
  auto paper_run = [paper](auto get) {
    return [paper, get](const RunRecord& r) {
      const PaperRun* pr = paper != nullptr ? paper->run(r.formulation, r.integrator) : nullptr;
      return pr != nullptr ? paper_number(get(*pr)) : std::string("-");
    };
  };
  auto paper_model = [paper](const std::optional<double>& v) {
    return [v, paper](const RunRecord& r) {
      // The paper gives one number for the model; show it beside the
      // formulations it ran, with its integrator.
      return paper != nullptr && paper->run(r.formulation, r.integrator) != nullptr
                 ? paper_number(v)
                 : std::string("-");
    };
  };
  const PaperNumbers empty;
  const PaperNumbers& p = paper != nullptr ? *paper : empty;

  add_row(
      row::kStatus, [&c](size_t i) { return status(c.runs[i]); }, none);
  add_row(row::kSteps, metric([](const RunMetrics& m) { return std::to_string(m.steps); }), none);
  add_row(row::kAvgIterations,
          metric([](const RunMetrics& m) { return fmt("%.4f", m.avg_iterations); }),
          paper_run([](const PaperRun& r) { return r.avg_iterations; }));
  add_row(row::kMaxIterations,
          metric([](const RunMetrics& m) { return std::to_string(m.max_iterations); }),
          paper_run([](const PaperRun& r) { return r.max_iterations; }));
  add_row(row::kWall, metric([](const RunMetrics& m) { return g4(m.wall_seconds); }),
          paper_run([](const PaperRun& r) { return r.total_seconds; }));
  add_row(row::kPerStep, metric([](const RunMetrics& m) { return g4(m.seconds_per_step * 1e3); }),
          none);
  add_row(row::kWorstStep,
          metric([](const RunMetrics& m) { return g4(m.worst_step_seconds * 1e3); }), none);
  add_row(row::kWorstStepTime, metric([](const RunMetrics& m) { return g4(m.worst_step_time); }),
          none);
  add_row(row::kRealTime, metric([](const RunMetrics& m) { return g4(m.real_time_factor); }), none);
  add_row(row::kDrift, metric([](const RunMetrics& m) { return g4(m.peak_abs_drift); }),
          paper_model(p.peak_drift));
  add_row(row::kDriftTime, metric([](const RunMetrics& m) { return g4(m.peak_drift_time); }),
          paper_model(p.peak_drift_time));
  add_row(row::kWork, metric([](const RunMetrics& m) { return g4(m.max_abs_work); }),
          paper_model(p.max_actuator_work));
  add_row(row::kDriftPercent, metric([](const RunMetrics& m) {
            return m.drift_percent ? g4(*m.drift_percent) : std::string("n/a");
          }),
          paper_model(p.peak_drift_percent));
  add_row(row::kPhi, metric([](const RunMetrics& m) { return e3(m.max_phi_norm); }), none);
  add_row(
      row::kPartition, [&c](size_t i) { return coordinates_in_use(c.runs[i]); },
      [paper](const RunRecord& r) {
        const PaperRun* pr = paper != nullptr ? paper->run(r.formulation, r.integrator) : nullptr;
        return pr != nullptr && !pr->coordinates.empty() ? pr->coordinates : std::string("-");
      });
  add_row(
      row::kCounters, [&c](size_t i) { return counters_at_end(c.runs[i]); }, none);

  if (ref != nullptr) {
    auto difference = [&c](auto get) {
      return [&c, get](size_t i) {
        const auto& d = c.differences[i];
        if (!d) return std::string("-");
        const std::optional<double> v = get(*d);
        return v ? e3(*v) : std::string("-");
      };
    };
    add_row("max |dz| from " + ref->label,
            difference([](const Differences& d) { return d.max_abs_z; }), none);
    for (size_t k = 0; k < c.pressures.size(); ++k)
      add_row("max |d" + c.pressures[k] + "| from " + ref->label + " (Pa)",
              difference([k](const Differences& d) { return d.pressures[k]; }), none);
  }

  for (const auto& r : c.runs)
    if (r.failed) t.notes.push_back(r.label + " FAILED: " + r.failure);
  if (ref != nullptr && ref != &c.runs.front())
    t.notes.push_back("differences are from " + ref->label + ", the first run with results");
  for (size_t i = 0; i < c.runs.size(); ++i)
    if (c.differences[i] && c.runs[i].rows() != ref->rows())
      t.notes.push_back(c.runs[i].label + ": differences over the " +
                        std::to_string(c.differences[i]->rows) + " rows both runs have");
  if (paper != nullptr) {
    std::string source = "paper: " + (p.source.empty() ? std::string("the paper") : p.source);
    if (!p.platform.empty()) source += "; its times were measured in " + p.platform;
    if (!p.integrator.empty())
      source += "; its numbers are for the " + p.integrator + " integrator";
    t.notes.push_back(source);
  }
  return t;
}

std::string render_text(const TextTable& table) {
  std::vector<size_t> width(table.header.size(), 0);
  auto widen = [&width](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size() && i < width.size(); ++i)
      width[i] = std::max(width[i], cells[i].size());
  };
  widen(table.header);
  for (const auto& r : table.rows) widen(r);
  std::ostringstream out;
  auto line = [&out, &width](const std::vector<std::string>& cells) {
    std::string text;
    for (size_t i = 0; i < cells.size(); ++i) {
      text += cells[i];
      if (i + 1 < cells.size()) text += std::string(width[i] - cells[i].size() + 2, ' ');
    }
    out << text << '\n';
  };
  out << table.title << '\n';
  line(table.header);
  size_t total = 0;
  for (size_t w : width) total += w + 2;
  out << std::string(total > 2 ? total - 2 : 0, '-') << '\n';
  for (const auto& r : table.rows) line(r);
  for (const auto& n : table.notes) out << "  " << n << '\n';
  return out.str();
}

}  // namespace mh::cli
