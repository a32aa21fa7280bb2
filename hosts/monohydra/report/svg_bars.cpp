#include "svg_bars.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "monohydra/cpp/number_text.hpp"
#include "svg_plot.hpp"

namespace mh::cli {
namespace {

constexpr double kRowHeight = 22.0;
constexpr double kBarHeight = 14.0;
constexpr double kTop = 30.0;
constexpr double kBottom = 40.0;  // the axis's ticks and title
constexpr double kRight = 90.0;   // room for the value after the longest bar
constexpr double kCharWidth = 6.6;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

}  // namespace

std::string svg_bars(const BarSpec& spec, const std::vector<Bar>& bars) {
  size_t longest = 0;
  double top_value = 0.0;
  for (const Bar& b : bars) {
    longest = std::max(longest, b.label.size());
    top_value = std::max(top_value, b.value);
  }
  const double left = 12.0 + kCharWidth * static_cast<double>(longest);
  const double inner = std::max(80.0, spec.width - left - kRight);
  const std::vector<double> ticks = nice_ticks(0.0, top_value > 0.0 ? top_value : 1.0, 5);
  const double axis_max = std::max(ticks.empty() ? 1.0 : ticks.back(), top_value);
  auto x_of = [&](double v) { return left + inner * (axis_max > 0.0 ? v / axis_max : 0.0); };
  const double height = kTop + kRowHeight * static_cast<double>(bars.size()) + kBottom;
  const double axis_y = kTop + kRowHeight * static_cast<double>(bars.size());

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << xml_escape(spec.id)
    << "\" class=\"plot\" width=\"" << spec.width << "\" height=\"" << num(height)
    << "\" viewBox=\"0 0 " << spec.width << ' ' << num(height)
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<title>" << xml_escape(spec.title) << "</title>\n";
  o << "<text x=\"" << num(left) << "\" y=\"18\" font-weight=\"bold\">" << xml_escape(spec.title)
    << "</text>\n";
  for (double t : ticks) {
    o << "<line x1=\"" << num(x_of(t)) << "\" y1=\"" << num(kTop - 4.0) << "\" x2=\""
      << num(x_of(t)) << "\" y2=\"" << num(axis_y) << "\" stroke=\"#e4e4e4\"/>\n";
    o << "<text x=\"" << num(x_of(t)) << "\" y=\"" << num(axis_y + 16.0)
      << "\" text-anchor=\"middle\">" << xml_escape(monohydra::short_number(t)) << "</text>\n";
  }
  o << "<line x1=\"" << num(left) << "\" y1=\"" << num(axis_y) << "\" x2=\"" << num(left + inner)
    << "\" y2=\"" << num(axis_y) << "\" stroke=\"#333\"/>\n";
  o << "<text x=\"" << num(left + 0.5 * inner) << "\" y=\"" << num(axis_y + 34.0)
    << "\" text-anchor=\"middle\">" << xml_escape(spec.unit) << "</text>\n";
  for (size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const double y = kTop + kRowHeight * static_cast<double>(i);
    const double v = std::max(0.0, b.value);
    o << "<text x=\"" << num(left - 6.0) << "\" y=\"" << num(y + kBarHeight - 2.0)
      << "\" text-anchor=\"end\">" << xml_escape(b.label) << "</text>\n";
    o << "<rect class=\"bar\" x=\"" << num(left) << "\" y=\"" << num(y) << "\" width=\""
      << num(x_of(v) - left) << "\" height=\"" << num(kBarHeight) << "\" fill=\""
      << xml_escape(b.colour) << "\"><title>" << xml_escape(b.label) << ": "
      << xml_escape(monohydra::short_number(b.value)) << ' ' << xml_escape(spec.unit)
      << "</title></rect>\n";
    o << "<text x=\"" << num(x_of(v) + 4.0) << "\" y=\"" << num(y + kBarHeight - 2.0) << "\">"
      << xml_escape(monohydra::short_number(b.value)) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace mh::cli
