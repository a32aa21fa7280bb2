// The example models the control components declare
// (mh_subsystem_factory.example_model): small model files on which `monohydra
// check monohydra-control.so` checks each component (its jacobian against
// differences, its restart) without a model of the user's.
#pragma once

namespace ctl {

// Every signal block in one chain, driven by a ramp and a step, with the
// limits reached during the run so that both sides of each kink are checked.
inline constexpr const char* kBlocksExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: lag, type: first-order-lag, input: [[0, 0], [0.2, 0], [0.6, 2], [1, 2]], time_constant: 0.05, gain: 1.5}
  - {name: k, type: gain, input: lag.y, gain: 2}
  - {name: sat, type: saturation, input: k.y, lower: -1, upper: 4}
  - {name: rate, type: rate-limiter, input: sat.y, rising: 5, falling: 2, time_constant: 0.02}
  - {name: error, type: sum, a: [[0, 1], [1, 1]], b: rate.y, k_b: -1}
  - {name: pi, type: pi-controller, setpoint: [[0, 0.5], [1, 0.5]], measurement: rate.y, kp: 2, ki: 4, output_min: -1, output_max: 1}
  - {name: pid, type: pid-controller, setpoint: error.y, measurement: pi.u, kp: 1, ki: 2, kd: 0.05, filter_time_constant: 0.02, output_min: -3, output_max: 3}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// The sensors on a swinging pendulum and a hose charged through a throttle.
inline constexpr const char* kSensorsExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, -9.81, 0]
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 0, 1]},
     mass: 2.0, com: [0.5, 0, 0], inertia: [0.1, 0.1, 0.2], z0: 0.3}
subsystems:
  - {name: length, type: distance-sensor, points: {a: {body: ground, at: [0, -2, 0]}, b: {body: arm, at: [1, 0, 0]}}, offset: 1}
  - {name: tip, type: point-sensor, points: {p: {body: arm, at: [1, 0, 0]}}}
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: line, type: throttle, ports: {a: s, b: n}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: gauge, type: pressure-sensor, ports: {a: n}}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

}  // namespace ctl
