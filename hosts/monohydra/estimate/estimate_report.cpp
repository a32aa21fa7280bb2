// The estimate command's report (estimate_report.hpp).
#include "estimate_report.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "monohydra/cpp/number_text.hpp"
#include "svg_plot.hpp"

namespace mh::cli {

namespace {

std::string num(double v) {
  return std::isfinite(v) ? monohydra::short_number(v) : "-";
}

std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", 100.0 * fraction);
  return text;
}

bool has(const FilterTrack& f, Eigen::Index column) {
  return f.sd.cols() > column;
}

// The series of column `c` of `values` (steps x columns) at the steps where
// it is a number: a sampled signal drawn through its samples.
PlotSeries samples(const std::string& label, const std::vector<double>& t,
                   const Eigen::MatrixXd& values, Eigen::Index c, const std::string& colour,
                   const std::string& dash) {
  PlotSeries s{label, {}, {}, colour, dash};
  for (Eigen::Index k = 0; k < values.rows(); ++k)
    if (std::isfinite(values(k, c))) {
      s.x.push_back(t[static_cast<size_t>(k)]);
      s.y.push_back(values(k, c));
    }
  return s;
}

}  // namespace

void attach_truth(EstimateReport& report, const MeasuredData& truth, double dt) {
  const auto n = static_cast<Eigen::Index>(report.states.size());
  const Eigen::Index steps = report.measured.rows();
  report.truth_path = truth.path;
  report.truth_column.assign(report.states.size(), -1);
  report.nees_dof = 0;
  for (size_t i = 0; i < report.states.size(); ++i)
    for (size_t c = 0; c < truth.names.size(); ++c)
      if (truth.names[c] == report.states[i]) {
        report.truth_column[i] = static_cast<int>(c);
        ++report.nees_dof;
      }
  if (report.nees_dof == 0) {
    std::string names;
    for (const std::string& s : report.states) names += (names.empty() ? "" : ", ") + s;
    throw std::invalid_argument(truth.path + ": no column is a state of the filter (" + names +
                                ")");
  }
  report.truth = Eigen::MatrixXd::Constant(steps, n, NAN);
  for (size_t row = 0; row < truth.t.size(); ++row) {
    const long k = std::lround(truth.t[row] / dt);
    if (k < 0 || k >= steps || std::abs(truth.t[row] - static_cast<double>(k) * dt) > 0.25 * dt)
      continue;
    for (Eigen::Index i = 0; i < n; ++i) {
      const int c = report.truth_column[static_cast<size_t>(i)];
      if (c >= 0) report.truth(k, i) = truth.values[static_cast<size_t>(c)][row];
    }
  }
}

double nees_at(const EstimateReport& report, Eigen::Index k, const Eigen::VectorXd& estimate,
               const Eigen::MatrixXd& covariance) {
  if (report.nees_dof == 0 || k >= report.truth.rows()) return NAN;
  std::vector<Eigen::Index> index;
  for (size_t i = 0; i < report.truth_column.size(); ++i)
    if (report.truth_column[i] >= 0) index.push_back(static_cast<Eigen::Index>(i));
  const auto m = static_cast<Eigen::Index>(index.size());
  Eigen::VectorXd e(m);
  Eigen::MatrixXd p(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    e[a] = estimate[index[static_cast<size_t>(a)]] - report.truth(k, index[static_cast<size_t>(a)]);
    for (Eigen::Index b = 0; b < m; ++b)
      p(a, b) = covariance(index[static_cast<size_t>(a)], index[static_cast<size_t>(b)]);
  }
  if (!e.allFinite()) return NAN;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(p);
  if (ldlt.info() != Eigen::Success) return NAN;
  return e.dot(ldlt.solve(e));
}

std::string estimate_report_html(const EstimateReport& r) {
  std::ostringstream out;
  const std::string title = "monohydra estimate: " + r.model + " on " + r.data_path;
  const Eigen::Index steps = r.measured.rows();
  out << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\" "
         "xml:lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>"
      << xml_escape(title)
      << "</title>\n<style>body { font-family: sans-serif; max-width: 860px; margin: 1em auto; "
         "color: #222; } table { border-collapse: collapse; font-size: 13px; margin-bottom: "
         "1em; } td, th { border: 1px solid #ccc; padding: 2px 8px; } figure svg { max-width: "
         "100%; height: auto; }</style>\n</head>\n<body>\n<h1>"
      << xml_escape(title) << "</h1>\n<p>" << steps << " steps, " << r.sensors.size() << " sensors";
  for (const FilterTrack& f : r.filters)
    out << "; " << xml_escape(f.label) << " " << num(f.cpu_seconds) << " s of CPU";
  out << (r.truth_path.empty() ? "" : "; the truth: " + xml_escape(r.truth_path)) << ".</p>\n";

  if (!r.truth_path.empty()) {
    // RMS error and the share of steps inside the 2-sigma band, per state.
    out << "<h2>Error against the truth</h2>\n<table>\n<tr><th>state</th>";
    for (const FilterTrack& f : r.filters) {
      out << "<th>" << xml_escape(f.label) << ": RMS error</th>";
      if (has(f, 0))
        out << "<th>" << xml_escape(f.label) << ": of the open loop's</th><th>"
            << xml_escape(f.label) << ": inside 2 sigma</th>";
    }
    out << "</tr>\n";
    for (size_t i = 0; i < r.states.size(); ++i) {
      if (r.truth_column[i] < 0) continue;
      const auto c = static_cast<Eigen::Index>(i);
      out << "<tr><td>" << xml_escape(r.states[i]) << " (" << xml_escape(r.units[i]) << ")</td>";
      double open_rms = NAN, scale = 0.0;
      for (Eigen::Index k = 0; k < steps; ++k)
        if (std::isfinite(r.truth(k, c))) scale = std::max(scale, std::abs(r.truth(k, c)));
      for (const FilterTrack& f : r.filters) {
        double squares = 0.0, inside = 0.0, count = 0.0;
        for (Eigen::Index k = 0; k < steps; ++k) {
          const double e = f.estimate(k, c) - r.truth(k, c);
          if (!std::isfinite(e)) continue;
          squares += e * e;
          count += 1.0;
          if (has(f, c) && std::abs(e) <= 2.0 * f.sd(k, c)) inside += 1.0;
        }
        const double rms = count > 0.0 ? std::sqrt(squares / count) : NAN;
        if (!has(f, 0)) open_rms = rms;
        out << "<td>" << num(rms) << "</td>";
        // No ratio to an open loop that is exact (a state nothing perturbs).
        if (has(f, 0))
          out << "<td>" << (open_rms > 1e-9 * scale ? num(rms / open_rms) : "-") << "</td><td>"
              << percent(count > 0.0 ? inside / count : NAN) << "</td>";
      }
      out << "</tr>\n";
    }
    out << "</table>\n";
    // NEES against the two-sided 95 % band of a chi-square of the truth's states.
    const boost::math::chi_squared chi(static_cast<double>(r.nees_dof));
    const double low = boost::math::quantile(chi, 0.025), high = boost::math::quantile(chi, 0.975);
    out << "<h2>Normalised estimation error squared</h2>\n<p>e<sup>T</sup> P<sup>-1</sup> e "
           "over the "
        << r.nees_dof << " states the truth has, against the two-sided 95 % band of a "
        << "chi-square of " << r.nees_dof << " degrees of freedom, [" << num(low) << ", "
        << num(high)
        << "]: a consistent filter is inside it 95 % of the steps; above it, it is surer of "
           "its state than its errors allow; below, more doubtful.</p>\n<table>\n<tr><th>filter"
           "</th><th>inside</th><th>above</th><th>below</th></tr>\n";
    for (const FilterTrack& f : r.filters) {
      if (!has(f, 0)) continue;
      double inside = 0.0, above = 0.0, below = 0.0;
      for (const double v : f.nees) {
        if (!std::isfinite(v)) continue;
        (v > high ? above : v < low ? below : inside) += 1.0;
      }
      const double count = inside + above + below;
      out << "<tr><td>" << xml_escape(f.label) << "</td><td>" << percent(inside / count)
          << "</td><td>" << percent(above / count) << "</td><td>" << percent(below / count)
          << "</td></tr>\n";
    }
    out << "</table>\n";
  }

  out << "<h2>The states</h2>\n";
  const std::vector<double>& t = r.filters.front().t;
  for (size_t i = 0; i < r.states.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    std::vector<PlotSeries> series;
    for (size_t j = 0; j < r.filters.size(); ++j) {
      const FilterTrack& f = r.filters[j];
      if (!has(f, 0)) {
        if (c < f.estimate.cols())
          series.push_back(samples(f.label, t, f.estimate, c, "#888888", dash_pattern(1)));
        continue;
      }
      series.push_back(samples(f.label, t, f.estimate, c, palette(j), ""));
      const Eigen::MatrixXd upper = f.estimate + 2.0 * f.sd, lower = f.estimate - 2.0 * f.sd;
      series.push_back(samples(f.label + " +2 sigma", t, upper, c, palette(j), dash_pattern(2)));
      series.push_back(samples(f.label + " -2 sigma", t, lower, c, palette(j), dash_pattern(2)));
    }
    if (!r.truth_path.empty() && r.truth_column[i] >= 0)  // on top
      series.push_back(samples("truth", t, r.truth, c, "#000000", ""));
    PlotSpec spec;
    spec.id = "state-" + std::to_string(i);
    spec.title = r.states[i];
    spec.x_label = "t (s)";
    spec.y_label = r.states[i] + (r.units[i].empty() ? "" : " (" + r.units[i] + ")");
    out << "<figure>" << svg_plot(spec, series) << "</figure>\n";
  }
  out << "<h2>The sensors: measured, and what each filter expected</h2>\n";
  for (size_t s = 0; s < r.sensors.size(); ++s) {
    const auto c = static_cast<Eigen::Index>(s);
    std::vector<PlotSeries> series{samples("measured", t, r.measured, c, "#000000", "")};
    for (size_t j = 0; j < r.filters.size(); ++j)
      if (has(r.filters[j], 0))
        series.push_back(samples(r.filters[j].label, t, r.filters[j].predicted, c, palette(j), ""));
    PlotSpec spec;
    spec.id = "sensor-" + std::to_string(s);
    spec.title = r.sensors[s];
    spec.x_label = "t (s)";
    spec.y_label = r.sensors[s] + " (SI)";
    out << "<figure>" << svg_plot(spec, series) << "</figure>\n";
  }
  out << "</body>\n</html>\n";
  return out.str();
}

}  // namespace mh::cli
