#include "case_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "results_table.hpp"
#include "run_metrics.hpp"

namespace mh::cli::sweep {
namespace {

std::string column_list(const RunRecord& run) {
  std::string out;
  for (const auto& n : run.names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool is_coordinate(const std::string& name) {
  return name.size() > 1 && name[0] == 'z' &&
         name.find_first_not_of("0123456789", 1) == std::string::npos;
}

// The columns `names` of a run's CSV after its header; a row that does not fit
// the header is refused (a reference is whole: case_run.cpp).
ReferenceRun read_columns(std::istream& in, const std::vector<std::string>& header,
                          const std::vector<std::string>& names, const std::string& csv_path) {
  std::string line;
  std::vector<int> wanted;  // column index per name, -1 when absent
  for (const auto& n : names) {
    const auto it = std::find(header.begin(), header.end(), n);
    wanted.push_back(it == header.end() ? -1 : static_cast<int>(it - header.begin()));
  }
  ReferenceRun ref;
  std::vector<std::vector<double>> cols(names.size());
  while (std::getline(in, line)) {
    const auto fields = split_csv_line(line);
    if (fields.size() != header.size())
      throw std::runtime_error("'" + csv_path + "' has a row of " + std::to_string(fields.size()) +
                               " fields under a header of " + std::to_string(header.size()));
    ref.t.push_back(std::stod(fields[0]));
    for (std::size_t i = 0; i < names.size(); ++i)
      if (wanted[i] >= 0) cols[i].push_back(std::stod(fields[static_cast<std::size_t>(wanted[i])]));
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    if (wanted[i] >= 0) ref.columns[names[i]] = std::move(cols[i]);
  return ref;
}

const std::vector<double>& column(const RunRecord& run, const std::string& name) {
  if (run.column(name) < 0)
    throw std::invalid_argument("no column '" + name + "' in the run's results (it has " +
                                column_list(run) + ")");
  return run.values(name);
}

}  // namespace

ReferenceRun load_reference(const std::string& csv_path, const std::vector<std::string>& names) {
  std::ifstream in(csv_path);
  std::string line;
  if (!in || !std::getline(in, line)) throw std::runtime_error("cannot read '" + csv_path + "'");
  const auto header = split_csv_line(line);
  std::vector<std::string> all = names;  // "z": every coordinate column z1..zN
  if (std::find(names.begin(), names.end(), "z") != names.end())
    for (const auto& h : header)
      if (is_coordinate(h) && std::find(all.begin(), all.end(), h) == all.end()) all.push_back(h);
  return read_columns(in, header, all, csv_path);
}

std::optional<double> max_abs_error(const std::vector<double>& t, const std::vector<double>& x,
                                    const ReferenceRun& reference, const std::string& name) {
  const auto it = reference.columns.find(name);
  if (it == reference.columns.end() || reference.t.size() < 2 || t.empty()) return std::nullopt;
  const auto& tr = reference.t;
  const auto& xr = it->second;
  const double slack = 1e-9 * std::max(1.0, std::abs(tr.back()));
  if (t.front() < tr.front() - slack || t.back() > tr.back() + slack) return std::nullopt;
  double worst = 0.0;
  std::size_t k = 0;  // tr[k] <= t[i] < tr[k + 1]: both increase
  for (std::size_t i = 0; i < t.size(); ++i) {
    while (k + 2 < tr.size() && tr[k + 1] <= t[i]) ++k;
    const double span = tr[k + 1] - tr[k];
    const double f = span > 0 ? std::clamp((t[i] - tr[k]) / span, 0.0, 1.0) : 0.0;
    const double ref = xr[k] + f * (xr[k + 1] - xr[k]);
    worst = std::max(worst, std::abs(x[i] - ref));
  }
  return worst;
}

std::vector<std::optional<double>> case_metrics(
    const Study& study, const RunRecord& run,
    const std::map<std::string, const ReferenceRun*>& references) {
  const RunMetrics m = compute_metrics(run);
  std::vector<std::optional<double>> out;
  for (const auto& spec : study.metrics) {
    const std::string& k = spec.kind;
    if (k == "peak_drift") {
      out.emplace_back(m.peak_abs_drift);
    } else if (k == "drift_percent") {
      out.push_back(m.drift_percent);
    } else if (k == "max_phi_norm") {
      out.emplace_back(m.max_phi_norm);
    } else if (k == "newton_iterations") {
      double total = 0.0;  // every step's, not the start's
      if (run.rows() > 0) {
        const auto& iters = run.values("iters");
        for (std::size_t r = 1; r < iters.size(); ++r) total += iters[r];
      }
      out.emplace_back(total);
    } else if (k == "mean_iterations") {
      out.emplace_back(m.avg_iterations);
    } else if (k == "steps") {
      out.emplace_back(static_cast<double>(m.steps));
    } else if (run.rows() == 0) {
      column(run, spec.column);  // a missing column is an error even without rows
      out.emplace_back(std::nullopt);
    } else if (k == "max" || k == "min" || k == "final") {
      const auto& v = column(run, spec.column);
      out.emplace_back(k == "max"   ? *std::max_element(v.begin(), v.end())
                       : k == "min" ? *std::min_element(v.begin(), v.end())
                                    : v.back());
    } else {  // error; "z": the largest over the coordinates z1..zN
      std::vector<std::string> names = {spec.column};
      if (spec.column == "z") {
        names.clear();
        for (int j = 1; j <= run.num_coordinates; ++j)
          names.push_back(run.names[static_cast<std::size_t>(j)]);
      }
      const auto it = references.find(spec.reference);
      std::optional<double> worst;
      for (const auto& name : names) {
        const auto& v = column(run, name);
        if (it == references.end() || it->second == nullptr) continue;
        const auto e = max_abs_error(run.values("t"), v, *it->second, name);
        if (!e) {
          worst.reset();
          break;
        }
        worst = std::max(worst.value_or(0.0), *e);
      }
      out.push_back(worst);
    }
  }
  return out;
}

}  // namespace mh::cli::sweep
