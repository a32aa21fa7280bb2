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

// The run's rows at every whole second (t = 0, 1, 2, ...); a run shorter than
// 2 s gives five frames evenly spread over it instead. Empty without rows.
std::vector<MechanismFrame> frames_every_second(const RunRecord& run);

// One <g class="frame"> per frame, coloured light (first) to dark (last).
std::string svg_mechanism(const ModelFile& file, const std::vector<MechanismFrame>& frames,
                          const std::string& id, const std::string& title);

}  // namespace mh::cli
