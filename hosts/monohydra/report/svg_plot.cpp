#include "svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "monohydra/cpp/number_text.hpp"

namespace mh::cli {
namespace {

constexpr double kLeft = 78.0;  // room for the y tick labels and axis title
constexpr double kRight = 16.0;
constexpr double kTop = 30.0;
constexpr double kBottom = 44.0;  // x tick labels and axis title
constexpr double kLegendRow = 18.0;
constexpr double kCharWidth = 6.6;  // of the 12 px sans-serif, to lay out the legend

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

std::string tick_label(double v) {
  if (v == 0.0 || (std::abs(v) < 1e5 && std::abs(v) >= 1e-3)) return monohydra::short_number(v);
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.0e", v);
  return buf;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};

struct LegendItem {
  std::string label;
  std::string colour;
  std::string dash;
  bool swatch = false;  // a filled box (the shading) instead of a line
};

}  // namespace

const char* palette(size_t index) {
  static const char* const colours[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                        "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
  return colours[index % 10];
}

const char* dash_pattern(size_t index) {
  static const char* const dashes[] = {"", "7 4", "2 3", "8 3 2 3"};
  return dashes[index % 4];
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (int i = 0; i < 1000; ++i) {
    const double v = first + i * step;
    if (v > hi + step * 1e-9) break;
    ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return ticks;
}

std::vector<size_t> decimate_min_max(const std::vector<double>& x, const std::vector<double>& y,
                                     double x0, double x1, int buckets) {
  std::vector<size_t> out;
  const size_t n = std::min(x.size(), y.size());
  if (n == 0) return out;
  if (buckets < 1 || !(x1 > x0) || n <= 4 * static_cast<size_t>(buckets)) {
    for (size_t i = 0; i < n; ++i) out.push_back(i);
    return out;
  }
  auto bucket_of = [&](size_t i) {
    const double f = (x[i] - x0) / (x1 - x0);
    return std::clamp(static_cast<long>(f * buckets), 0L, static_cast<long>(buckets) - 1);
  };
  size_t i = 0;
  while (i < n) {
    const long b = bucket_of(i);
    size_t first = i, lowest = i, highest = i, last = i;
    for (; i < n && bucket_of(i) == b; ++i) {
      last = i;
      if (y[i] < y[lowest] || !std::isfinite(y[lowest])) lowest = i;
      if (y[i] > y[highest] || !std::isfinite(y[highest])) highest = i;
      if (!std::isfinite(y[i])) {  // keep line breaks
        out.push_back(i);
      }
    }
    std::vector<size_t> keep{first, lowest, highest, last};
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    for (size_t k : keep) out.push_back(k);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string svg_plot(const PlotSpec& spec, const std::vector<PlotSeries>& series) {
  const std::string& id = spec.id;
  const double w = spec.width;
  const double plot_w = w - kLeft - kRight;
  const double plot_h = spec.plot_height;

  // Ranges.
  Range xr, yr;
  for (const auto& s : series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      xr.add(s.x[i]);
      if (!spec.log_y || s.y[i] > 0.0) yr.add(spec.log_y ? std::log10(s.y[i]) : s.y[i]);
    }
  }
  if (xr.empty()) xr = Range{0.0, 1.0};
  if (xr.hi == xr.lo) xr = Range{xr.lo - 0.5, xr.hi + 0.5};
  std::vector<double> yticks;
  if (spec.log_y) {
    if (yr.empty()) yr = Range{-1.0, 0.0};
    yr.lo = std::floor(yr.lo);
    yr.hi = std::max(std::ceil(yr.hi), yr.lo + 1.0);
    const int decades = static_cast<int>(yr.hi - yr.lo);
    const int every = std::max(1, (decades + 7) / 8);
    for (int d = static_cast<int>(yr.lo); d <= static_cast<int>(yr.hi); d += every)
      yticks.push_back(d);
  } else {
    if (yr.empty()) yr = Range{0.0, 1.0};
    if (yr.hi - yr.lo <= 1e-12 * std::max(1.0, std::abs(yr.hi))) {
      const double pad = std::max(1.0, std::abs(yr.hi)) * 0.5;
      yr = Range{yr.lo - pad, yr.hi + pad};
    } else {
      const double pad = (yr.hi - yr.lo) * 0.05;
      yr = Range{yr.lo - pad, yr.hi + pad};
    }
    yticks = nice_ticks(yr.lo, yr.hi, 6);
  }
  auto px = [&](double x) { return kLeft + (x - xr.lo) / (xr.hi - xr.lo) * plot_w; };
  auto py = [&](double y) {
    double v = y;
    if (spec.log_y) v = y > 0.0 ? std::log10(y) : yr.lo;
    v = std::clamp(v, yr.lo, yr.hi);
    return kTop + (yr.hi - v) / (yr.hi - yr.lo) * plot_h;
  };

  // Legend layout, flowing below the x axis title.
  std::vector<LegendItem> legend;
  if (!spec.shaded.empty() && !spec.shade_label.empty())
    legend.push_back({spec.shade_label, spec.shade_colour, "", true});
  for (const auto& s : series) legend.push_back({s.label, s.colour, s.dash, false});
  struct Placed {
    double x, y;
  };
  std::vector<Placed> placed;
  double lx = kLeft, ly = kTop + plot_h + kBottom + 4.0;
  for (const auto& item : legend) {
    const double item_w = 34.0 + kCharWidth * static_cast<double>(item.label.size()) + 18.0;
    if (lx + item_w > w - kRight && lx > kLeft) {
      lx = kLeft;
      ly += kLegendRow;
    }
    placed.push_back({lx, ly});
    lx += item_w;
  }
  const double height = (legend.empty() ? kTop + plot_h + kBottom : ly + kLegendRow) + 4.0;

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << xml_escape(id) << "\" class=\"plot\""
    << " width=\"" << num(w) << "\" height=\"" << num(height) << "\" viewBox=\"0 0 " << num(w)
    << ' ' << num(height) << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<title>" << xml_escape(spec.title) << "</title>\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << num(w) << "\" height=\"" << num(height)
    << "\" fill=\"#ffffff\"/>\n";
  o << "<defs><clipPath id=\"" << xml_escape(id) << "-clip\"><rect x=\"" << num(kLeft) << "\" y=\""
    << num(kTop) << "\" width=\"" << num(plot_w) << "\" height=\"" << num(plot_h)
    << "\"/></clipPath></defs>\n";
  o << "<text x=\"" << num(w / 2) << "\" y=\"18\" text-anchor=\"middle\" font-weight=\"bold\">"
    << xml_escape(spec.title) << "</text>\n";

  // Shading under everything else.
  for (const auto& iv : spec.shaded) {
    const double a = px(std::max(iv.begin, xr.lo)), b = px(std::min(iv.end, xr.hi));
    if (!(b >= a)) continue;
    o << "<rect class=\"shade\" x=\"" << num(a) << "\" y=\"" << num(kTop) << "\" width=\""
      << num(std::max(b - a, 1.0)) << "\" height=\"" << num(plot_h) << "\" fill=\""
      << spec.shade_colour << "\"/>\n";
  }

  // Grid and ticks.
  o << "<g class=\"axes\" stroke=\"#d0d0d0\" stroke-width=\"1\">\n";
  const std::vector<double> xticks = nice_ticks(xr.lo, xr.hi, 10);
  for (double x : xticks)
    o << "<line x1=\"" << num(px(x)) << "\" y1=\"" << num(kTop) << "\" x2=\"" << num(px(x))
      << "\" y2=\"" << num(kTop + plot_h) << "\"/>\n";
  for (double y : yticks) {
    const double yy = spec.log_y ? py(std::pow(10.0, y)) : py(y);
    o << "<line x1=\"" << num(kLeft) << "\" y1=\"" << num(yy) << "\" x2=\"" << num(kLeft + plot_w)
      << "\" y2=\"" << num(yy) << "\"/>\n";
  }
  o << "</g>\n<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (double x : xticks)
    o << "<text x=\"" << num(px(x)) << "\" y=\"" << num(kTop + plot_h + 16)
      << "\" text-anchor=\"middle\">" << tick_label(x) << "</text>\n";
  for (double y : yticks) {
    const double yy = spec.log_y ? py(std::pow(10.0, y)) : py(y);
    const std::string label =
        spec.log_y ? "1e" + std::to_string(static_cast<int>(y)) : tick_label(y);
    o << "<text x=\"" << num(kLeft - 6) << "\" y=\"" << num(yy + 4) << "\" text-anchor=\"end\">"
      << label << "</text>\n";
  }
  o << "</g>\n";
  o << "<rect x=\"" << num(kLeft) << "\" y=\"" << num(kTop) << "\" width=\"" << num(plot_w)
    << "\" height=\"" << num(plot_h) << "\" fill=\"none\" stroke=\"#333333\"/>\n";
  o << "<text x=\"" << num(kLeft + plot_w / 2) << "\" y=\"" << num(kTop + plot_h + 34)
    << "\" text-anchor=\"middle\">" << xml_escape(spec.x_label) << "</text>\n";
  o << "<text transform=\"translate(14 " << num(kTop + plot_h / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">" << xml_escape(spec.y_label) << "</text>\n";

  // Series.
  o << "<g clip-path=\"url(#" << xml_escape(id) << "-clip)\" fill=\"none\" stroke-width=\"1.5\""
    << " stroke-linejoin=\"round\">\n";
  for (const auto& s : series) {
    const auto keep = decimate_min_max(s.x, s.y, xr.lo, xr.hi, static_cast<int>(plot_w));
    std::string d;
    bool pen_down = false;
    for (size_t i : keep) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        pen_down = false;
        continue;
      }
      d += (pen_down ? " L" : (d.empty() ? "M" : " M")) + num(px(s.x[i])) + ' ' + num(py(s.y[i]));
      pen_down = true;
    }
    o << "<path class=\"series\" stroke=\"" << s.colour << '"';
    if (!s.dash.empty()) o << " stroke-dasharray=\"" << s.dash << '"';
    o << " d=\"" << (d.empty() ? "M0 0" : d) << "\"><title>" << xml_escape(s.label)
      << "</title></path>\n";
  }
  o << "</g>\n";

  // Legend.
  o << "<g class=\"legend\">\n";
  for (size_t i = 0; i < legend.size(); ++i) {
    const auto& item = legend[i];
    const double x = placed[i].x, y = placed[i].y;
    if (item.swatch) {
      o << "<rect x=\"" << num(x) << "\" y=\"" << num(y - 9) << "\" width=\"28\" height=\"12\""
        << " fill=\"" << item.colour << "\"/>\n";
    } else {
      o << "<line x1=\"" << num(x) << "\" y1=\"" << num(y - 3) << "\" x2=\"" << num(x + 28)
        << "\" y2=\"" << num(y - 3) << "\" stroke=\"" << item.colour << "\" stroke-width=\"2\"";
      if (!item.dash.empty()) o << " stroke-dasharray=\"" << item.dash << '"';
      o << "/>\n";
    }
    o << "<text x=\"" << num(x + 34) << "\" y=\"" << num(y + 1) << "\">" << xml_escape(item.label)
      << "</text>\n";
  }
  o << "</g>\n</svg>\n";
  return o.str();
}

}  // namespace mh::cli
