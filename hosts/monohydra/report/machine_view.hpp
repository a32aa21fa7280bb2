// The report's animated 3D view of the machine: every body drawn from its
// shape (a default glyph without one), its joints, the ground, each
// component as it declared its look (visual.h: an actuator's barrel and rod,
// a link), or as a line between its points when it declared none; chambers
// coloured by pressure; the compared runs overlaid (the first solid, the
// others as ghosts). The page holds everything: three.js (Debian's
// libjs-three, built in), the viewer and the frames, decimated to the display
// rate. How to read it and the canvas's attributes: docs/compare.md.
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "monohydra/core/plugin_registry.hpp"
#include "monohydra/core/simulation.hpp"
#include "report_html.hpp"
#include "run_record.hpp"

namespace mh::cli {

// What the components declared of their look, and the result column of every
// state (to colour by), from a run set up once and never stepped.
struct ViewDeclarations {
  std::vector<Visual> visuals;
  std::vector<std::string> state_columns;  // Simulation::state_names()
  std::string note;                        // why there are none, when setup failed
};
ViewDeclarations view_declarations(const ModelFile& file, const PluginRegistry& registry,
                                   const std::vector<std::string>& formulations);

inline constexpr double kViewFramesPerSecond = 30.0;  // of simulated time

// The frames' data as one JavaScript statement (window.MH_VIEW = {...};).
// Runs without rows are left out; `runs` must not be empty.
std::string machine_view_data(const ModelFile& file, const ViewDeclarations& declared,
                              const std::vector<const RunRecord*>& runs,
                              double frames_per_second = kViewFramesPerSecond);

// Whether this build holds three.js (the view needs it).
bool machine_view_available();

// The view's section of the page (canvas, controls, legend, caption and the
// scripts, each in a CDATA section so that the page stays well-formed XML).
// "" when !machine_view_available().
std::string machine_view_html(const std::string& data_script);

// Gives the page its 3D view of `runs` (page.view), or says why it has none
// (page.view_note); a fact line says the view's size.
void add_machine_view(ReportPage& page, const ModelFile& file, const PluginRegistry& registry,
                      const std::vector<const RunRecord*>& runs,
                      const std::vector<std::string>& formulations);

}  // namespace mh::cli
