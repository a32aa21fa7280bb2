// The example model the earth-moving components declare
// (mh_subsystem_factory.example_model): a 200 kg blade on a horizontal slide,
// its edge 0.1 m below the ground, thrown forward at 1 m/s into loose sand
// and stopped by it, on which `monohydra check monohydra-earthmoving.so`
// checks bucket-soil without a model of the user's.
#pragma once

namespace earth {

inline constexpr const char* kBladeExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: blade, parent: ground, joint: {type: prismatic, at: [0, 0, -0.1], axis: [1, 0, 0]},
     mass: 200.0, com: [0, 0, 0], inertia: [10, 10, 10], z0: 0.0, zd0: 1.0}
subsystems:
  - {name: sand, type: bucket-soil, width: 1.0, density: 1600, friction_angle: 0.5236,
     interface_friction: 0.349, edge_thickness: 0.02,
     points: {edge: {body: blade, at: [0, 0, 0]}, heel: {body: blade, at: [-0.23, 0, 0.19]},
              side: {body: blade, at: [0, -0.5, 0]}}}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

}  // namespace earth
