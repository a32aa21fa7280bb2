// Horizontal bar charts as standalone SVG (well-formed XML, no scripts): one
// labelled bar per item, drawn to scale from zero, with its value written at
// its end. For quantities that add up, as the energy each part of a circuit
// dissipated over a run.
#pragma once

#include <string>
#include <vector>

namespace mh::cli {

struct Bar {
  std::string label;
  double value = 0.0;  // >= 0, in the chart's unit
  std::string colour;  // "#rrggbb"
};

struct BarSpec {
  std::string id;  // unique in the document: every SVG id inside starts with it
  std::string title;
  std::string unit;  // written after each value and under the axis, e.g. "kJ"
  int width = 820;
};

// The chart as an <svg> element with the SVG namespace; each bar is one
// <rect class="bar"> in the order given.
std::string svg_bars(const BarSpec& spec, const std::vector<Bar>& bars);

}  // namespace mh::cli
