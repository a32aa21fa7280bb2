// The components of the hydraulics plugin library (docs/hydraulics.md), each
// defined in its own file.
#pragma once

#include "monohydra/cpp/subsystem_component.hpp"

namespace hyd {

extern const monohydra::SubsystemComponent kPressureSource;       // pressure_source.cpp
extern const monohydra::SubsystemComponent kFlowSource;           // flow_source.cpp
extern const monohydra::SubsystemComponent kVolume;               // volume.cpp
extern const monohydra::SubsystemComponent kThrottle;             // throttle.cpp
extern const monohydra::SubsystemComponent kValve43;              // valve_4_3.cpp
extern const monohydra::SubsystemComponent kCylinder;             // cylinder.cpp
extern const monohydra::SubsystemComponent kReliefValve;          // relief_valve.cpp
extern const monohydra::SubsystemComponent kCheckValve;           // check_valve.cpp
extern const monohydra::SubsystemComponent kHydraulicMotor;       // hydraulic_motor.cpp
extern const monohydra::SubsystemComponent kValveTable;           // valve_table.cpp
extern const monohydra::SubsystemComponent kHose;                 // hose.cpp
extern const monohydra::SubsystemComponent kCounterbalanceValve;  // counterbalance_valve.cpp
extern const monohydra::SubsystemComponent kPilotCheckValve;      // pilot_check_valve.cpp
extern const monohydra::SubsystemComponent kVariablePump;         // variable_pump.cpp
extern const monohydra::SubsystemComponent kLsValveSection;       // ls_valve_section.cpp
extern const monohydra::SubsystemComponent kShuttleValve;         // shuttle_valve.cpp
extern const monohydra::SubsystemComponent kOpenCentreValve;      // open_centre_valve.cpp

}  // namespace hyd
