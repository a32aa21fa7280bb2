// An excavator's tool forces as ISO 6015 rates them (Sect. 5.2, "rated tool
// forces"): the force at the bucket lip, tangent to the arc it describes
// about the pivot of the joint a cylinder turns (the bucket's for the bucket
// cylinder, the arm's for the arm cylinder), when that cylinder alone pushes
// with the circuit's relief pressure on its cap side; no gravity, no
// friction. By virtual work, F = p A |dL/dtheta| / r: L the cylinder's length,
// theta the joint's angle, r the lip's distance from the joint's axis; dL/dtheta
// through any linkage between them (the loops closed at each angle). ISO
// reports the largest over the positions the cylinder drives, and the pose
// it is at.
#pragma once

#include <string>
#include <vector>

#include "monohydra/core/model.hpp"

namespace mh {

struct ToolForceSpec {
  int coordinate = -1;  // the revolute joint the cylinder turns (body index = coordinate)
  BodyPoint lip;        // the bucket lip's middle
  BodyPoint cylinder_a, cylinder_b;
  double area = 0.0;                                    // m^2, the side the pressure pushes on
  double pressure = 0.0;                                // Pa
  double length_min = 0.0, length_max = 0.0;            // m, the cylinder's stroke: |b - a| in it
  double step = 0.25 * 3.14159265358979323846 / 180.0;  // rad, the scan's
};

struct ToolForcePoint {
  double angle = 0.0;   // rad, the joint's coordinate
  double length = 0.0;  // m
  double lever = 0.0;   // dL/dtheta, m/rad
  double radius = 0.0;  // m
  double force = 0.0;   // N
};

struct ToolForce {
  ToolForcePoint largest;
  ToolForcePoint initial;               // at the model's own pose
  std::vector<ToolForcePoint> samples;  // the scan, in increasing angle
};

// The scan over the joint's angle from the model's initial pose both ways,
// the joint and the bodies of model.assembly_fixed held,
// the others moved to close the loops, while the loops close, the cylinder
// stays in its stroke and turns the joint the way it does at the model's
// pose (up to a dead point, where dL/dtheta passes zero). Throws std::invalid_argument naming what
// is missing (a coordinate that is not a revolute joint, loops that do not close at the model's
// pose, a cylinder out of its stroke there).
ToolForce tool_force(const Model& model, const ToolForceSpec& spec);

}  // namespace mh
