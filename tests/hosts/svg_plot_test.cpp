// Line plots (hosts/monohydra/svg_plot.cpp): decimation keeps every spike,
// ticks are round, and the SVG holds one path per series and one rectangle
// per shaded interval, with nothing that is not a number in its coordinates.
#include "svg_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace mh::test {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(SvgPlot, DecimationKeepsASingleSampleSpikeAndBothEnds) {
  std::vector<double> x, y;
  for (int i = 0; i < 100000; ++i) {
    x.push_back(i * 1e-4);
    y.push_back(i == 61234 ? 7.0 : std::sin(i * 1e-4));
  }
  const auto keep = cli::decimate_min_max(x, y, 0.0, 10.0, 700);
  EXPECT_LE(keep.size(), 4u * 700u);
  EXPECT_EQ(keep.front(), 0u);
  EXPECT_EQ(keep.back(), 99999u);
  EXPECT_NE(std::find(keep.begin(), keep.end(), 61234u), keep.end());
  EXPECT_TRUE(std::is_sorted(keep.begin(), keep.end()));
}

TEST(SvgPlot, ShortSeriesAreDrawnWhole) {
  const std::vector<double> x{0, 1, 2}, y{3, 1, 2};
  EXPECT_EQ(cli::decimate_min_max(x, y, 0, 2, 700).size(), 3u);
}

TEST(SvgPlot, TicksAreRoundAndInsideTheRange) {
  EXPECT_EQ(cli::nice_ticks(0.0, 10.0, 10),
            (std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  const auto t = cli::nice_ticks(-0.013, 0.0021, 6);
  ASSERT_FALSE(t.empty());
  for (double v : t) {
    EXPECT_GE(v, -0.013);
    EXPECT_LE(v, 0.0021);
  }
  // 0.0151 / 6 = 0.0025 per tick asked: the next round step is 0.005.
  EXPECT_NEAR(t[1] - t[0], 0.005, 1e-15);
  EXPECT_EQ(t.size(), 3u);  // -0.01, -0.005, 0
}

TEST(SvgPlot, OnePathPerSeriesAndOneRectanglePerShadedInterval) {
  cli::PlotSpec spec;
  spec.id = "p";
  spec.title = "Pressures & <flows>";
  spec.shaded = {{1.0, 2.5}, {5.0, 8.0}};
  spec.shade_label = "valve open";
  std::vector<cli::PlotSeries> series(3);
  for (size_t s = 0; s < series.size(); ++s) {
    series[s].label = "p" + std::to_string(s);
    series[s].colour = cli::palette(s);
    for (int i = 0; i <= 100; ++i) {
      series[s].x.push_back(i * 0.1);
      series[s].y.push_back(static_cast<double>(s) * i);
    }
  }
  const std::string svg = cli::svg_plot(spec, series);
  EXPECT_EQ(count(svg, "<path class=\"series\""), 3u);
  EXPECT_EQ(count(svg, "<rect class=\"shade\""), 2u);
  EXPECT_NE(svg.find("Pressures &amp; &lt;flows&gt;"), std::string::npos);
  EXPECT_NE(svg.find("clip-path=\"url(#p-clip)\""), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

TEST(SvgPlot, LogScaleDrawsZerosOnTheAxisAndSkipsNonFiniteValues) {
  cli::PlotSpec spec;
  spec.id = "c";
  spec.log_y = true;
  cli::PlotSeries s;
  s.colour = "#000000";
  s.x = {0, 1, 2, 3, 4};
  s.y = {0.0, 1e-15, NAN, 1e-11, 0.0};
  const std::string svg = cli::svg_plot(spec, {s});
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_NE(svg.find(">1e-15<"), std::string::npos);  // a decade tick at the smallest value
  EXPECT_NE(svg.find(">1e-11<"), std::string::npos);
  // The NaN breaks the line: two pieces.
  const size_t path = svg.find("<path class=\"series\"");
  const std::string d = svg.substr(path, svg.find("</path>", path) - path);
  EXPECT_EQ(count(d, "M"), 2u);
}

TEST(SvgPlot, XmlEscapeCoversMarkupAndQuotes) {
  EXPECT_EQ(cli::xml_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
}

}  // namespace
}  // namespace mh::test
