// The example model the mechanics components declare
// (mh_subsystem_factory.example_model, filled from each component's
// kExampleModel): a slider held by a spring-damper and a Maxwell element, on
// which `monohydra check monohydra-mechanics.so` checks both without a model
// of the user's.
#pragma once

namespace mech {

inline constexpr const char* kSliderExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 2.0, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0.1}
subsystems:
  - {name: holder, type: spring-damper, stiffness: 50, damping: 3, free_length: 1.0,
     points: {a: {body: ground, at: [-1, 0, 0]}, b: {body: slider, at: [0, 0, 0]}}}
  - {name: creep, type: maxwell, stiffness: 50, damping: 3, free_length: 1.0, tolerance: 1e-9,
     points: {a: {body: ground, at: [-1, 0, 0]}, b: {body: slider, at: [0, 0, 0]}}}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

}  // namespace mech
