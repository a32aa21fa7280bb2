// The components of the control plugin library (docs/control.md), each
// defined in its own file: signal blocks whose outputs are states of the run,
// wired by name (option_signal_port), and sensors that turn the mechanics and
// the hydraulics into signals.
#pragma once

#include "monohydra/cpp/subsystem_component.hpp"

namespace ctl {

extern const monohydra::SubsystemComponent kGain;            // gain.cpp
extern const monohydra::SubsystemComponent kSum;             // sum.cpp
extern const monohydra::SubsystemComponent kSaturation;      // saturation.cpp
extern const monohydra::SubsystemComponent kRateLimiter;     // rate_limiter.cpp
extern const monohydra::SubsystemComponent kFirstOrderLag;   // first_order_lag.cpp
extern const monohydra::SubsystemComponent kPiController;    // pid_controller.cpp
extern const monohydra::SubsystemComponent kPidController;   // pid_controller.cpp
extern const monohydra::SubsystemComponent kDistanceSensor;  // distance_sensor.cpp
extern const monohydra::SubsystemComponent kPointSensor;     // point_sensor.cpp
extern const monohydra::SubsystemComponent kPressureSensor;  // pressure_sensor.cpp

}  // namespace ctl
