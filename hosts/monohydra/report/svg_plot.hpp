// Line plots as standalone SVG (well-formed XML, no scripts, no external
// resources): axes with round ticks, series decimated to the plot's pixels
// without losing their peaks, shaded x intervals and a legend.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "xml_text.hpp"

namespace mh::cli {

struct PlotSeries {
  std::string label;
  std::vector<double> x;  // increasing
  std::vector<double> y;  // same length; non-finite values break the line
  std::string colour;     // "#rrggbb"
  std::string dash;       // SVG stroke-dasharray, "" for a solid line
};

struct PlotInterval {
  double begin = 0.0;
  double end = 0.0;
};

struct PlotSpec {
  std::string id;  // unique in the document: every SVG id inside starts with it
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_y = false;  // values <= 0 are drawn on the bottom of the axis
  std::vector<PlotInterval> shaded;
  std::string shade_colour = "#d8c8f0";
  std::string shade_label;  // legend text of the shading
  int width = 820;
  int plot_height = 260;  // of the plotting area; the legend adds below it
};

// The plot as an <svg> element (with the SVG namespace, so it stands alone
// or inline in XHTML). Each series is one <path class="series">, each shaded
// interval one <rect class="shade">.
std::string svg_plot(const PlotSpec& spec, const std::vector<PlotSeries>& series);

// About `target` round ticks (1, 2 or 5 times a power of ten) within [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int target);

// Indices of the points to draw for `buckets` pixel columns over [x0, x1]:
// the first and last point, and in each column its first, lowest, highest and
// last point, in order. A series of 10^4 points draws in ~4 per pixel and
// keeps every spike.
std::vector<size_t> decimate_min_max(const std::vector<double>& x, const std::vector<double>& y,
                                     double x0, double x1, int buckets);

// Text made safe for XML content and attribute values (hosts/common).
using host::xml_escape;

// A colour of a 10-colour palette (Tableau 10), by index (wraps).
const char* palette(size_t index);
// Dash patterns that tell runs apart: solid, dashed, dotted, dash-dot (wraps).
const char* dash_pattern(size_t index);

}  // namespace mh::cli
