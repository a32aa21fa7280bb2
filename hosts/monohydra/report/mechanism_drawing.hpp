// The mechanism drawn at several instants in one SVG (the paper's Fig. 6),
// projected on the XY plane (a 3D model: side, top and isometric views, one
// above the other), from the model alone: every body from its joint
// point to its other points, cut joints, ground points and each subsystem's
// points (a line between the two points of a two-point element, e.g. an
// actuator). How each body is drawn: docs/compare.md.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "monohydra/core/model_file.hpp"
#include "run_record.hpp"

namespace mh::cli {

struct MechanismFrame {
  double t = 0.0;     // s
  Eigen::VectorXd z;  // relative joint coordinates
};

// The directions a 3D model is looked at along: up against gravity (Y
// without gravity), h1 the world axis most nearly level made level, h2 = up x
// h1; `iso_eye` is the isometric view's direction towards the eye (from h1's
// side, the near side and above). The 2D drawing's views and the 3D view's
// first camera both come from here.
struct ViewAxes {
  Eigen::Vector3d up, h1, h2, iso_eye;
};
ViewAxes view_axes(const Model& m);

// The run's rows at every whole second (t = 0, 1, 2, ...); a run shorter than
// 2 s gives five frames evenly spread over it instead. Empty without rows.
std::vector<MechanismFrame> frames_every_second(const RunRecord& run);

// One <g class="frame"> per frame, coloured light (first) to dark (last).
std::string svg_mechanism(const ModelFile& file, const std::vector<MechanismFrame>& frames,
                          const std::string& id, const std::string& title);

}  // namespace mh::cli
