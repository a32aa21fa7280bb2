// The control plugin library: one entry symbol, one subsystem factory that
// lists the signal blocks and sensors.
#include "components.hpp"

MONOHYDRA_SUBSYSTEM_PLUGIN(ctl::kGain, ctl::kSum, ctl::kSaturation, ctl::kRateLimiter,
                           ctl::kFirstOrderLag, ctl::kPiController, ctl::kPidController,
                           ctl::kDistanceSensor, ctl::kPointSensor, ctl::kPressureSensor);
