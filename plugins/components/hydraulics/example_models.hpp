// The example models the hydraulic components declare
// (mh_subsystem_factory.example_model, filled from each component's
// kExampleModel): small model files that use each component with example
// options, on which `monohydra check monohydra-hydraulics.so` checks it
// without a model of the user's.
#pragma once

namespace hyd {

// Throttle, volume and pressure-source: a hose charged from a pump through a throttle.
inline constexpr const char* kThrottleExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: line, type: throttle, ports: {a: s, b: n}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A 10 m hose from a pump to a small volume that drains through a throttle.
inline constexpr const char* kHoseExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: hose, type: hose, ports: {a: s, b: end}, length: 10, inner_diameter: 0.012, density: 850, viscosity: 0.03, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, segments: 5, initial_pressure: 8e6}
  - {name: end, type: volume, ports: {p: end}, volume: 1e-5, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9}
  - {name: drain, type: throttle, ports: {a: end, b: tank}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
formulation: open-loop
solver: {dt: 0.0001, t_end: 0.05}
)";

// A hose charged from a pump through a check valve.
inline constexpr const char* kCheckValveExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: valve, type: check-valve, ports: {A: s, B: n}, cracking_pressure: 1e5, override_pressure: 5e5, nominal_flow: 1e-5}
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A constant flow into a hose, relieved to the tank (also flow-source).
inline constexpr const char* kReliefValveExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: flow-source, ports: {p: n}, flow: 1e-5}
  - {name: hose, type: volume, ports: {p: n}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: relief, type: relief-valve, ports: {P: n, T: tank}, cracking_pressure: 1.5e6, override_pressure: 5e5, nominal_flow: 1e-4}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A 4/3 valve opening between pump, tank and two hoses.
inline constexpr const char* kValve43Example = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 10.0, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0}
subsystems:
  - {name: valve, type: valve-4-3, ports: {P: s, T: tank, A: a, B: b}, flow_coefficient: 2e-8, time_constant: 5e-3,
     reference: [[0, 0], [0.005, 0], [0.005, 5], [1, 5]]}
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
  - {name: hose_a, type: volume, ports: {p: a}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: hose_b, type: volume, ports: {p: b}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// The same with a measured flow table.
inline constexpr const char* kValveTableExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 10.0, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0}
subsystems:
  - {name: valve, type: valve-table, ports: {P: s, T: tank, A: a, B: b}, time_constant: 5e-3,
     reference: [[0, 0], [0.005, 0], [0.005, 5], [1, 5]],
     flow_table: [[0, 1e5, 0], [0, 1e7, 0], [5, 1e5, 6e-6], [5, 1e7, 6e-5], [10, 1e5, 1.2e-5], [10, 1e7, 1.2e-4]]}
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
  - {name: hose_a, type: volume, ports: {p: a}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: hose_b, type: volume, ports: {p: b}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A cylinder pushing a slider, fed and drained through throttles.
inline constexpr const char* kCylinderExample = R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 10.0, com: [0, 0, 0], inertia: [1, 1, 1], z0: 0}
subsystems:
  - {name: ram, type: cylinder, points: {a: {body: ground, at: [-1, 0, 0]}, b: {body: slider, at: [0, 0, 0]}},
     ports: {A: a, B: b}, piston_diameter: 0.05, rod_diameter: 0.025, length: 1.0, chamber_bulk_modulus: 31500e6,
     fluid_bulk_modulus: 1500e6, efficiency: 0.9}
  - {name: pump, type: pressure-source, ports: {p: s}, pressure: 8e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
  - {name: in, type: throttle, ports: {a: s, b: a}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
  - {name: out, type: throttle, ports: {a: b, b: tank}, area: 1e-6, discharge_coefficient: 0.7, density: 850}
  - {name: hose_a, type: volume, ports: {p: a}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
  - {name: hose_b, type: volume, ports: {p: b}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e6}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A motor turning an arm against gravity.
inline constexpr const char* kHydraulicMotorExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, -9.81]
bodies:
  - {name: arm, parent: ground, joint: {type: revolute, at: [0, 0, 0], axis: [0, 1, 0]},
     mass: 50, com: [0.5, 0, 0], inertia: [3, 3, 2]}
subsystems:
  - {name: pump, type: pressure-source, ports: {p: supply}, pressure: 10e6}
  - {name: tank, type: pressure-source, ports: {p: return}, pressure: 1e5}
  - name: motor
    type: hydraulic-motor
    points:
      housing: {body: ground, at: [0, 0, 0]}
      rotor: {body: arm, at: [0, 0.3, 0]}
      housing_arm: {body: ground, at: [0.2, 0, 0]}
      rotor_arm: {body: arm, at: [0, 0.3, 0.2]}
    ports: {A: supply, B: return}
    displacement: 8e-6
    leakage_coefficient: 1e-12
    viscous_friction: 0.8
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

}  // namespace hyd

// A 1 t load on a vertical cylinder (cap side down, 2 MPa to hold it), its
// cap chamber held by a counterbalance valve piloted from the rod side
// through a damping orifice (without it the valve and the load's oil spring
// oscillate, as real ones do); from 1 s the pump fills the rod side at
// 0.2 l/s and the load is lowered at 0.2 l/s over the rod side's area, the
// cap side's oil passing the valve and a metering orifice to tank.
inline constexpr const char* kCounterbalanceValveExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, -9.81, 0]
planar: true
bodies:
  - {name: load, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [0, 1, 0]},
     mass: 1000, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: cylinder, type: cylinder, points: {a: {body: ground, at: [0, -2, 0]}, b: {body: load, at: [0, 0, 0]}},
     ports: {A: cap, B: rod}, piston_diameter: 0.08, rod_diameter: 0.04, length: 1.2,
     chamber_bulk_modulus: 2e10, fluid_bulk_modulus: 1.5e9, efficiency: 0.9}
  - {name: V_cap, type: volume, ports: {p: cap}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9}
  - {name: V_rod, type: volume, ports: {p: rod}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: V_line, type: volume, ports: {p: line}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: V_pilot, type: volume, ports: {p: pilot}, volume: 1e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: pilot_orifice, type: throttle, ports: {a: rod, b: pilot}, area: 5e-8, discharge_coefficient: 0.7, density: 850}
  - {name: cbv, type: counterbalance-valve, ports: {L: cap, V: line, X: pilot}, setting_pressure: 4e6,
     pilot_ratio: 3, override_pressure: 5e6, nominal_flow: 3e-4}
  - {name: pump, type: flow-source, ports: {p: rod}, flow: [[0, 0], [1, 0], [1.2, 2e-4], [100, 2e-4]]}
  - {name: metering, type: throttle, ports: {a: line, b: tank}, area: 2e-5, discharge_coefficient: 0.7, density: 850}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
equilibrium: {free: [cap]}
formulation: open-loop
solver: {dt: 0.001, t_end: 2}
)";

// The same load on a pilot-operated check valve: the pump fills the cap side
// through it (free flow) from 0.5 s to 1 s and the load rises, the rod side
// emptying to tank; then the valve holds it (the pilot, the rod side, near
// tank pressure).
inline constexpr const char* kPilotCheckValveExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, -9.81, 0]
planar: true
bodies:
  - {name: load, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [0, 1, 0]},
     mass: 1000, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: cylinder, type: cylinder, points: {a: {body: ground, at: [0, -2, 0]}, b: {body: load, at: [0, 0, 0]}},
     ports: {A: cap, B: rod}, piston_diameter: 0.08, rod_diameter: 0.04, length: 1.2,
     chamber_bulk_modulus: 2e10, fluid_bulk_modulus: 1.5e9, efficiency: 0.9}
  - {name: V_cap, type: volume, ports: {p: cap}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9}
  - {name: V_rod, type: volume, ports: {p: rod}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: V_line, type: volume, ports: {p: line}, volume: 2e-4, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: pocv, type: pilot-check-valve, ports: {A: line, B: cap, X: rod}, pilot_ratio: 4, nominal_flow: 1e-3}
  - {name: pump, type: flow-source, ports: {p: line}, flow: [[0, 0], [0.5, 0], [0.6, 2e-4], [0.9, 2e-4], [1, 0], [100, 0]]}
  - {name: rod_return, type: throttle, ports: {a: rod, b: tank}, area: 2e-5, discharge_coefficient: 0.7, density: 850}
  - {name: line_bleed, type: throttle, ports: {a: line, b: tank}, area: 1e-7, discharge_coefficient: 0.7, density: 850}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
equilibrium: {free: [cap]}
formulation: open-loop
solver: {dt: 0.001, t_end: 2, line_search: on}
)";

// A load-sensing pump (max 1.5 l/s) feeding one pre-compensated section that
// opens to 5 V from 0.1 s against a 10 MPa load; the section's LS port
// pilots the pump through a small line.
inline constexpr const char* kVariablePumpExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: variable-pump, ports: {P: supply, S: tank, LS: ls}, max_displacement: 1e-5,
     speed: 150, margin: 2e6, cutoff_pressure: 30e6, max_power: 60e3}
  - {name: V_supply, type: volume, ports: {p: supply}, volume: 1e-3, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 2.1e6}
  - {name: V_ls, type: volume, ports: {p: ls}, volume: 1e-5, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: section, type: ls-valve-section, ports: {P: supply, T: tank, A: load, B: tank, LS: ls},
     flow_coefficient: 2e-8, time_constant: 0.02, reference: [[0, 0], [0.1, 0], [0.2, 5], [10, 5]]}
  - {name: load, type: pressure-source, ports: {p: load}, pressure: 10e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// Two post-compensated sections (flow sharing) on a pump of at most 0.1 l/s,
// against 5 and 10 MPa loads; a shuttle sends the higher load pressure to
// the pump and to the compensators; both spools open from 0.1 s (4 V and 8
// V), asking for more than the pump gives.
inline constexpr const char* kLoadSensingExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: variable-pump, ports: {P: supply, S: tank, LS: ls}, max_displacement: 1e-6,
     speed: 100, margin: 2e6}
  - {name: V_supply, type: volume, ports: {p: supply}, volume: 1e-3, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 2.1e6}
  - {name: V_ls, type: volume, ports: {p: ls}, volume: 1e-5, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: V_ls1, type: volume, ports: {p: ls1}, volume: 1e-5, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: V_ls2, type: volume, ports: {p: ls2}, volume: 1e-5, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1e5}
  - {name: shuttle, type: shuttle-valve, ports: {A: ls1, B: ls2, C: ls}}
  - {name: section1, type: ls-valve-section, ports: {P: supply, T: tank, A: load1, B: tank, LS: ls1, X: ls},
     compensation: post, flow_coefficient: 2e-8, time_constant: 0.02, reference: [[0, 0], [0.1, 0], [0.2, 4], [10, 4]]}
  - {name: section2, type: ls-valve-section, ports: {P: supply, T: tank, A: load2, B: tank, LS: ls2, X: ls},
     compensation: post, flow_coefficient: 2e-8, time_constant: 0.02, reference: [[0, 0], [0.1, 0], [0.2, 8], [10, 8]]}
  - {name: load1, type: pressure-source, ports: {p: load1}, pressure: 5e6}
  - {name: load2, type: pressure-source, ports: {p: load2}, pressure: 10e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";

// A fixed pump (0.1 l/s) on an open-centre valve: in neutral the centre
// passes it to tank at 1 MPa; from 0.1 s to 0.5 s the spool opens to 10 V
// against an 8 MPa load, closing the centre at 6 V.
inline constexpr const char* kOpenCentreValveExample =
    R"(units: {length: m, mass: kg, time: s, angle: rad}
gravity: [0, 0, 0]
bodies:
  - {name: slider, parent: ground, joint: {type: prismatic, at: [0, 0, 0], axis: [1, 0, 0]},
     mass: 1.0, com: [0, 0, 0], inertia: [1, 1, 1]}
subsystems:
  - {name: pump, type: flow-source, ports: {p: supply}, flow: 1e-4}
  - {name: V_supply, type: volume, ports: {p: supply}, volume: 1e-3, bulk_modulus: 1e9, fluid_bulk_modulus: 1.5e9, initial_pressure: 1.1e6}
  - {name: valve, type: open-centre-valve, ports: {P: supply, T: tank, A: load, B: tank}, flow_coefficient: 2e-8,
     nominal_bypass_flow: 1e-4, bypass_pressure: 1e6, closing_spool: 6, time_constant: 0.02,
     reference: [[0, 0], [0.1, 0], [0.5, 10], [10, 10]]}
  - {name: relief, type: relief-valve, ports: {P: supply, T: tank}, cracking_pressure: 20e6, override_pressure: 2e6, nominal_flow: 2e-4}
  - {name: load, type: pressure-source, ports: {p: load}, pressure: 8e6}
  - {name: tank, type: pressure-source, ports: {p: tank}, pressure: 1e5}
formulation: open-loop
solver: {dt: 0.001, t_end: 1}
)";
