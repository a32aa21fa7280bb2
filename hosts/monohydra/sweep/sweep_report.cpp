#include "sweep_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "case_expansion.hpp"
#include "results_table.hpp"
#include "svg_plot.hpp"

namespace fs = std::filesystem;

namespace mh::cli::sweep {
namespace {

const char* const kStyle = R"(
body { font-family: sans-serif; max-width: 1100px; margin: 1em auto; padding: 0 1em; color: #222; }
h1 { font-size: 22px; } h2 { font-size: 18px; margin-top: 1.6em; }
table.sweep { border-collapse: collapse; font-size: 12px; }
table.sweep td, table.sweep th { border: 1px solid #cccccc; padding: 2px 6px; }
table.sweep td { text-align: right; } table.sweep td.text { text-align: left; }
table.sweep td.failed { color: #b00000; font-weight: bold; }
figure { margin: 1.2em 0; } figure svg { display: block; max-width: 100%; height: auto; }
)";

std::optional<double> number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

int column_of(const SweepTable& t, const std::string& name) {
  const auto it = std::find(t.header.begin(), t.header.end(), name);
  return it == t.header.end() ? -1 : static_cast<int>(it - t.header.begin());
}

bool numeric_column(const SweepTable& t, int c) {
  bool any = false;
  for (const auto& r : t.rows) {
    const std::string& v = r[static_cast<std::size_t>(c)];
    if (v.empty()) continue;
    if (!number(v)) return false;
    any = true;
  }
  return any;
}

// One plot of column y against column x, a series per group of rows.
std::string plot(const Study& study, const SweepTable& t, const std::string& x,
                 const std::string& y, bool log_x, bool log_y, const std::string& title,
                 const std::string& id, const std::string& model = "") {
  const int cx = column_of(t, x), cy = column_of(t, y), cs = column_of(t, "status");
  // The series: the model and, against a parameter, every other parameter's
  // value (a line is that parameter's effect alone); against a metric (a
  // work-precision plot), the text-valued parameters (a line per method,
  // through its step sizes).
  const auto paths = varied_paths(study);
  const bool against_parameter = std::find(paths.begin(), paths.end(), x) != paths.end();
  const int cm = column_of(t, "model");
  std::vector<int> group;
  if (model.empty()) group.push_back(cm);
  for (const auto& p : paths) {
    const int c = column_of(t, p);
    if (c != cx && (against_parameter || !numeric_column(t, c))) group.push_back(c);
  }
  std::map<std::string, std::vector<std::pair<double, double>>> points;
  std::vector<std::string> order;
  for (const auto& r : t.rows) {
    if (r[static_cast<std::size_t>(cs)] != "ok") continue;
    if (!model.empty() && r[static_cast<std::size_t>(cm)] != model) continue;
    auto vx = number(r[static_cast<std::size_t>(cx)]);
    auto vy = number(r[static_cast<std::size_t>(cy)]);
    if (!vx || !vy || (log_x && *vx <= 0)) continue;
    if (log_x) vx = std::log10(*vx);
    std::string key;
    for (int c : group) key += (key.empty() ? "" : " ") + r[static_cast<std::size_t>(c)];
    if (points.count(key) == 0) order.push_back(key);
    points[key].emplace_back(*vx, *vy);
  }
  std::vector<PlotSeries> series;
  for (std::size_t i = 0; i < order.size(); ++i) {
    auto& pts = points[order[i]];
    std::sort(pts.begin(), pts.end());
    PlotSeries s;
    s.label = order[i];
    for (const auto& [px, py] : pts) {
      s.x.push_back(px);
      s.y.push_back(py);
    }
    s.colour = palette(i);
    s.dash = dash_pattern(i / 10);
    series.push_back(std::move(s));
  }
  PlotSpec spec;
  spec.id = id;
  spec.title = title;
  spec.x_label = log_x ? "log10(" + x + ")" : x;
  spec.y_label = y;
  spec.log_y = log_y;
  return svg_plot(spec, series);
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

}  // namespace

SweepTable read_table(const std::string& csv_path) {
  std::ifstream in(csv_path);
  if (!in) throw std::runtime_error("cannot read '" + csv_path + "'");
  SweepTable t;
  std::string line;
  if (std::getline(in, line)) t.header = split_csv_line(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    auto fields = split_csv_line(line);
    fields.resize(t.header.size());
    t.rows.push_back(std::move(fields));
  }
  return t;
}

std::vector<std::string> sweep_figures(const Study& study, const SweepTable& t) {
  std::vector<std::string> svgs;
  int n = 0;
  for (const auto& p : study.plots) {
    if (column_of(t, p.x) < 0 || column_of(t, p.y) < 0) continue;  // checked when loading
    svgs.push_back(plot(study, t, p.x, p.y, p.log_x, p.log_y, p.title,
                        "study-plot-" + std::to_string(++n), p.model));
  }
  std::vector<std::string> ys;
  for (const auto& m : study.metrics) ys.push_back(m.header);
  ys.emplace_back("cpu_s");
  for (const auto& path : varied_paths(study)) {
    const int cx = column_of(t, path);
    if (!numeric_column(t, cx)) continue;
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& r : t.rows)
      if (const auto v = number(r[static_cast<std::size_t>(cx)])) {
        lo = std::min(lo, *v);
        hi = std::max(hi, *v);
      }
    const bool log_x = lo > 0 && hi / lo >= 100;  // values over decades
    for (const auto& y : ys) {
      if (!numeric_column(t, column_of(t, y))) continue;
      svgs.push_back(plot(study, t, path, y, log_x, false, y + " against " + path,
                          "metric-plot-" + std::to_string(++n)));
    }
  }
  return svgs;
}

std::string write_sweep_report(const std::string& dir, const Study& study, const SweepTable& t) {
  std::ostringstream o;
  const std::string title = "Study " + study.name;
  o << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\" "
       "xml:lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>"
    << xml_escape(title) << "</title>\n<style>" << kStyle << "</style>\n</head>\n<body>\n<h1>"
    << xml_escape(title)
    << "</h1>\n<ul class=\"facts\">\n<li>study file: " << xml_escape(study.path)
    << "</li>\n<li>models:";
  for (const auto& m : study.models) o << ' ' << xml_escape(m.name + " (" + m.path + ")");
  std::map<std::string, int> statuses;
  const int cs = column_of(t, "status");
  for (const auto& r : t.rows) ++statuses[r[static_cast<std::size_t>(cs)]];
  o << "</li>\n<li>" << t.rows.size() << " cases:";
  for (const auto& [s, n] : statuses) o << ' ' << n << ' ' << xml_escape(s);
  o << "</li>\n</ul>\n<h2 id=\"table\">Results</h2>\n<p>The rows of results.csv "
       "(docs/sweeps.md defines every column; cpu_s and wall_s depend on the machine's "
       "load).</p>\n<table class=\"sweep\">\n<tr>";
  for (const auto& h : t.header) o << "<th>" << xml_escape(h) << "</th>";
  o << "</tr>\n";
  for (const auto& r : t.rows) {
    o << "<tr>";
    for (std::size_t i = 0; i < r.size(); ++i) {
      const bool bad = static_cast<int>(i) == cs && r[i] != "ok";
      // Numbers to 4 digits here; results.csv has every digit.
      const auto v = number(r[i]);
      char shown[32];
      if (v) std::snprintf(shown, sizeof shown, "%.4g", *v);
      o << "<td"
        << (bad  ? " class=\"failed\""
            : !v ? " class=\"text\""
                 : "")
        << ">" << xml_escape(v ? std::string(shown) : r[i]) << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n<h2 id=\"figures\">Figures</h2>\n<p>Against a parameter: one line per model "
       "and values of the other parameters. Against a metric: one line per model and values of "
       "the named (non-numeric) parameters. Only cases with status ok are drawn.</p>\n";
  const fs::path root(dir);
  std::error_code ec;
  fs::create_directories(root / "figures", ec);
  int n = 0;
  for (const auto& svg : sweep_figures(study, t)) {
    o << "<figure>\n" << svg << "</figure>\n";
    const std::string key = " id=\"";
    const std::size_t at = svg.find(key) + key.size();
    const std::string id = svg.substr(at, svg.find('"', at) - at);
    write_file(root / "figures" / ((id.empty() ? "figure-" + std::to_string(n) : id) + ".svg"),
               "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + svg);
    ++n;
  }
  o << "<h2 id=\"data\">Data</h2>\n<p><a href=\"results.csv\">results.csv</a></p>\n</body>\n"
       "</html>\n";
  const fs::path html = root / "report.html";
  write_file(html, o.str());
  return html.string();
}

}  // namespace mh::cli::sweep
