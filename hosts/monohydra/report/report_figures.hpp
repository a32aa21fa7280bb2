// The figures of the paper's Sect. 6 for one model, from the runs of a
// comparison: the mechanism at every second (Fig. 6), relative joint
// coordinates and pressures (Figs. 7-8), energies and drift (Figs. 9-10),
// constraint violation (Figs. 11-12), iterations and time per step
// (Figs. 13-14). Time plots shade where the model's control signals are on.
#pragma once

#include <string>
#include <vector>

#include "comparison.hpp"
#include "monohydra/core/model_file.hpp"
#include "svg_plot.hpp"

namespace mh::cli {

struct ReportFigure {
  std::string id;                 // e.g. "fig-coordinates": the HTML id, and the SVG files' stem
  std::string paper;              // the paper's figures it corresponds to, e.g. "Figs. 7a and 8a"
  std::string heading;            // what it shows
  std::string caption;            // how to read it; when svgs is empty, why it is left out
  std::vector<std::string> svgs;  // one or more panels (each an <svg> element)
};

// Every figure of the report, in the paper's order; a figure that does not
// apply to the model (no pressures, no cut joints) has no SVG and says why.
// `control_on` are the intervals to shade, `shade_colour` their colour.
std::vector<ReportFigure> report_figures(const ModelFile& file, const Comparison& c,
                                         const std::vector<PlotInterval>& control_on,
                                         const std::string& shade_colour);

// The ids report_figures gives, in order (the report holds each one).
const std::vector<std::string>& report_figure_ids();

}  // namespace mh::cli
