#include "fit_report.hpp"

#include <cmath>
#include <sstream>

#include "monohydra/cpp/number_text.hpp"
#include "svg_plot.hpp"

namespace mh::cli {

namespace {

std::string num(double v) {
  return std::isfinite(v) ? monohydra::short_number(v) : "-";
}

}  // namespace

TextTable estimates_table(const FitOutcome& o) {
  TextTable t;
  t.title = "estimates (95 % intervals: estimate +- 1.96 standard errors)";
  t.header = {"parameter", "initial", "estimate", "std error", "95 % interval", "identifiable"};
  for (size_t j = 0; j < o.run->paths().size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const ParameterStatistics& s = o.statistics->parameters[j];
    t.rows.push_back({o.run->paths()[j], num(o.run->initial()(i)), num(o.result->estimate(i)),
                      s.identifiable ? num(s.std_error) : "-",
                      s.identifiable ? "[" + num(s.ci_low) + ", " + num(s.ci_high) + "]" : "-",
                      s.identifiable ? "yes" : "NO"});
    if (!s.identifiable)
      t.notes.push_back(o.run->paths()[j] + " is not identifiable from these data: " + s.why +
                        "; its estimate is not a result");
  }
  return t;
}

TextTable correlation_table(const FitOutcome& o) {
  TextTable t;
  t.title = "correlation of the estimates";
  t.header = {"parameter"};
  const size_t k = o.run->paths().size();
  for (size_t j = 0; j < k; ++j) t.header.push_back("p" + std::to_string(j + 1));
  for (size_t a = 0; a < k; ++a) {
    std::vector<std::string> row{"p" + std::to_string(a + 1) + " " + o.run->paths()[a]};
    for (size_t b = 0; b < k; ++b) {
      const double c =
          o.statistics->correlation(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
      char text[16];
      std::snprintf(text, sizeof text, "%+.3f", c);
      row.emplace_back(std::isfinite(c) ? text : "-");
    }
    t.rows.push_back(row);
  }
  return t;
}

TextTable residual_table(const FitOutcome& o) {
  TextTable t;
  t.title = "residual RMS per measured column (model - measured)";
  t.header = {"column", "samples", "fitted", "initial", "weight (sigma)"};
  const std::vector<double> fitted = residual_rms(*o.run, o.result->predicted);
  const std::vector<double> initial = residual_rms(*o.run, o.result->predicted_initial);
  for (size_t c = 0; c < o.run->columns().size(); ++c) {
    const bool given = o.run->columns()[c].noise > 0.0;
    t.rows.push_back({o.run->columns()[c].name, std::to_string(o.data->count(c)), num(fitted[c]),
                      num(initial[c]),
                      num(o.result->sigma[c]) + (given ? " (given)" : " (its RMS)")});
  }
  return t;
}

std::string estimates_csv(const FitOutcome& o) {
  std::ostringstream out;
  out << "path,initial,estimate,std_error,ci_low,ci_high,identifiable\n";
  const auto exact = [](double v) { return std::isfinite(v) ? monohydra::exact_number(v) : ""; };
  for (size_t j = 0; j < o.run->paths().size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const ParameterStatistics& s = o.statistics->parameters[j];
    out << o.run->paths()[j] << ',' << exact(o.run->initial()(i)) << ','
        << exact(o.result->estimate(i)) << ',' << exact(s.std_error) << ',' << exact(s.ci_low)
        << ',' << exact(s.ci_high) << ',' << (s.identifiable ? 1 : 0) << '\n';
  }
  return out.str();
}

namespace {

void table_html(std::ostringstream& o, const TextTable& t) {
  o << "<h2>" << xml_escape(t.title) << "</h2>\n<table>\n<tr>";
  for (const std::string& h : t.header) o << "<th>" << xml_escape(h) << "</th>";
  o << "</tr>\n";
  for (const auto& r : t.rows) {
    o << "<tr>";
    for (const std::string& c : r) o << "<td>" << xml_escape(c) << "</td>";
    o << "</tr>\n";
  }
  o << "</table>\n";
  for (const std::string& n : t.notes) o << "<p class=\"note\">" << xml_escape(n) << "</p>\n";
}

}  // namespace

std::string fit_report_html(const FitOutcome& o) {
  std::ostringstream out;
  const std::string title = "monohydra fit: " + o.model_path + " against " + o.data->path;
  out << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\" "
         "xml:lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>"
      << xml_escape(title)
      << "</title>\n<style>body { font-family: sans-serif; max-width: 860px; margin: 1em auto; "
         "color: #222; } table { border-collapse: collapse; font-size: 13px; } td, th { border: "
         "1px solid #ccc; padding: 2px 8px; } p.note { color: #b00000; } figure svg { "
         "max-width: 100%; height: auto; }</style>\n</head>\n<body>\n<h1>"
      << xml_escape(title) << "</h1>\n<p>" << o.run->samples().size() << " samples, "
      << o.result->iterations << " Levenberg-Marquardt iterations, " << o.result->rounds
      << " round(s) of weights; cost 1/2 sum r^2 from " << num(o.result->initial_cost) << " to "
      << num(o.result->final_cost) << ".</p>\n";
  table_html(out, estimates_table(o));
  table_html(out, correlation_table(o));
  table_html(out, residual_table(o));
  out << "<h2>Measured, fitted and initial model</h2>\n";
  const SampledRun& run = *o.run;
  for (size_t c = 0; c < run.columns().size(); ++c) {
    PlotSeries measured{"measured", {}, {}, palette(0), ""};
    PlotSeries fitted{"fitted model", {}, {}, palette(1), ""};
    PlotSeries initial{"initial model", {}, {}, palette(2), dash_pattern(1)};
    for (size_t s = 0; s < run.samples().size(); ++s) {
      if (run.samples()[s].column != c) continue;
      const auto i = static_cast<Eigen::Index>(s);
      const double t = o.data->t[run.samples()[s].row];
      for (PlotSeries* p : {&measured, &fitted, &initial}) p->x.push_back(t);
      measured.y.push_back(run.measured()(i));
      fitted.y.push_back(o.result->predicted(i));
      initial.y.push_back(o.result->predicted_initial(i));
    }
    PlotSpec spec;
    spec.id = "fit-" + std::to_string(c);
    spec.title = run.columns()[c].name;
    spec.x_label = "t (s)";
    spec.y_label = run.columns()[c].name + " (SI)";
    out << "<figure>" << svg_plot(spec, {measured, initial, fitted}) << "</figure>\n";
  }
  out << "</body>\n</html>\n";
  return out.str();
}

}  // namespace mh::cli
