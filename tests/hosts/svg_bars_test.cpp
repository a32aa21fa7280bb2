// Horizontal bar charts (hosts/monohydra/report/svg_bars.cpp): every bar is
// there, in the order given, and drawn to scale from zero.
#include "svg_bars.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mh::cli {
namespace {

// The width of every <rect class="bar">, in order.
std::vector<double> widths(const std::string& svg) {
  std::vector<double> out;
  const std::string bar = "<rect class=\"bar\"", width = "width=\"";
  for (size_t at = svg.find(bar); at != std::string::npos; at = svg.find(bar, at + 1)) {
    const size_t w = svg.find(width, at) + width.size();
    out.push_back(std::stod(svg.substr(w, svg.find('"', w) - w)));
  }
  return out;
}

TEST(SvgBars, BarsAreInTheOrderGivenAndTheirLengthsProportionalToTheirValues) {
  const std::string svg = svg_bars(
      {"bars", "Energy", "kJ"},
      {{"valve <A&B>", 200.0, "#4e79a7"}, {"pump", 50.0, "#f28e2b"}, {"shuttle", 0.0, "#e15759"}});
  const auto w = widths(svg);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w[1] / w[0], 0.25, 0.002);  // to the 0.1 px the SVG writes
  EXPECT_EQ(w[2], 0.0);
  EXPECT_LT(svg.find("valve &lt;A&amp;B&gt;"), svg.find(">pump<"));
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"bars\"", 0), 0u);
}

TEST(SvgBars, ANegativeValueIsDrawnAsNoBarButWrittenAsItIs) {
  const std::string svg =
      svg_bars({"bars", "Energy", "kJ"}, {{"a", 10.0, "#4e79a7"}, {"b", -2.0, "#f28e2b"}});
  const auto w = widths(svg);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[1], 0.0);
  EXPECT_NE(svg.find(">-2<"), std::string::npos);
}

}  // namespace
}  // namespace mh::cli
