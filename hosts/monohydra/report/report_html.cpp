#include "report_html.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "svg_plot.hpp"

namespace fs = std::filesystem;

namespace mh::cli {
namespace {

const char* const kStyle = R"(
body { font-family: sans-serif; max-width: 860px; margin: 1em auto; padding: 0 1em; color: #222; }
h1 { font-size: 22px; } h2 { font-size: 18px; margin-top: 1.6em; } h3 { font-size: 15px; }
table.comparison { border-collapse: collapse; font-size: 13px; }
table.comparison td, table.comparison th { border: 1px solid #cccccc; padding: 2px 8px; }
table.comparison td { text-align: right; } table.comparison td.quantity { text-align: left; }
table.comparison .paper { background: #f2f2f2; color: #555555; }
table.comparison td.failed { color: #b00000; font-weight: bold; }
ul.notes { font-size: 13px; }
figure { margin: 1.2em 0; } figure svg { display: block; max-width: 100%; height: auto; }
figcaption { font-size: 13px; color: #444444; }
p.omitted { font-style: italic; color: #666666; }
.mh-view-box canvas { width: 820px; height: 520px; display: block; border: 1px solid #cccccc; }
.mh-controls { font-size: 13px; margin: 6px 0; display: flex; gap: 10px; align-items: center; }
.mh-controls input[type=range] { flex: 1; }
.mh-legend { font-size: 12px; display: flex; gap: 6px; align-items: center; }
.mh-legend .mh-bar { display: inline-block; width: 220px; height: 12px; border: 1px solid #999999; }
p.mh-caption { font-size: 13px; color: #444444; }
)";

// The id attribute of an <svg ...> element's text.
std::string svg_id(const std::string& svg) {
  const std::string key = " id=\"";
  const size_t at = svg.find(key);
  if (at == std::string::npos) return "figure";
  const size_t begin = at + key.size();
  return svg.substr(begin, svg.find('"', begin) - begin);
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

}  // namespace

std::string report_html(const ReportPage& page) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\" "
       "xml:lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>"
    << xml_escape(page.title) << "</title>\n<style>" << kStyle << "</style>\n</head>\n<body>\n";
  o << "<h1>" << xml_escape(page.title) << "</h1>\n<ul class=\"facts\">\n";
  for (const auto& f : page.facts) o << "<li>" << xml_escape(f) << "</li>\n";
  o << "</ul>\n";
  if (!page.view.empty())
    o << page.view;
  else if (!page.view_note.empty())
    o << "<h2 id=\"view\">The machine in motion</h2>\n<p class=\"omitted\">"
      << xml_escape(page.view_note) << "</p>\n";

  if (page.table != nullptr) {
    const TextTable& t = *page.table;
    o << "<h2 id=\"table\">Comparison</h2>\n<p>" << xml_escape(t.title)
      << "</p>\n<table class=\"comparison\">\n<tr>";
    for (const auto& h : t.header)
      o << "<th" << (h == "paper" ? " class=\"paper\"" : "") << ">" << xml_escape(h) << "</th>";
    o << "</tr>\n";
    for (const auto& r : t.rows) {
      o << "<tr>";
      for (size_t i = 0; i < r.size(); ++i) {
        std::string cls = i == 0 ? "quantity" : "";
        if (i < t.header.size() && t.header[i] == "paper") cls = "paper";
        if (i > 0 && r[i].rfind("FAILED", 0) == 0) cls = "failed";
        o << "<td" << (cls.empty() ? "" : " class=\"" + cls + "\"") << ">" << xml_escape(r[i])
          << "</td>";
      }
      o << "</tr>\n";
    }
    o << "</table>\n<ul class=\"notes\">\n";
    for (const auto& n : t.notes) o << "<li>" << xml_escape(n) << "</li>\n";
    o << "</ul>\n";
  }

  if (page.figures != nullptr) {
    o << "<h2 id=\"figures\">Figures (as in Sect. 6 of the paper)</h2>\n";
    for (const auto& f : *page.figures) {
      o << "<figure id=\"" << xml_escape(f.id) << "\">\n<h3>" << xml_escape(f.heading) << " ("
        << xml_escape(f.paper) << ")</h3>\n";
      if (f.svgs.empty()) o << "<p class=\"omitted\">" << xml_escape(f.caption) << "</p>\n";
      for (const auto& svg : f.svgs) o << svg;
      if (!f.svgs.empty()) o << "<figcaption>" << xml_escape(f.caption) << "</figcaption>\n";
      o << "</figure>\n";
    }
  }

  o << "<h2 id=\"data\">Data</h2>\n<ul class=\"data\">\n";
  for (const auto& csv : page.csv_files)
    o << "<li><a href=\"" << xml_escape(csv) << "\">" << xml_escape(csv) << "</a></li>\n";
  o << "</ul>\n<p>Columns: t, z1..zN, the written states and outputs, KE, PE, W, drift, "
       "phi_norm, iters, wall_s (docs/compare.md).</p>\n</body>\n</html>\n";
  return o.str();
}

std::string write_report(const std::string& dir, const ReportPage& page) {
  const fs::path root(dir);
  std::error_code ec;
  fs::create_directories(root / "figures", ec);
  if (ec) throw std::runtime_error("cannot create '" + (root / "figures").string() + "'");
  if (page.figures != nullptr)
    for (const auto& f : *page.figures)
      for (const auto& svg : f.svgs)
        write_file(root / "figures" / (svg_id(svg) + ".svg"),
                   "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + svg);
  const fs::path html = root / "report.html";
  write_file(html, report_html(page));
  return html.string();
}

}  // namespace mh::cli
