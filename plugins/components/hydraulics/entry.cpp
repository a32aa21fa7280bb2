// The hydraulics plugin library: one entry symbol, one subsystem factory that
// lists the components of a lumped-fluid circuit (Sect. 3 of the paper).
#include "components.hpp"

MONOHYDRA_SUBSYSTEM_PLUGIN(hyd::kPressureSource, hyd::kVolume, hyd::kThrottle, hyd::kValve43,
                           hyd::kCylinder, hyd::kReliefValve, hyd::kCheckValve,
                           hyd::kHydraulicMotor, hyd::kValveTable, hyd::kFlowSource, hyd::kHose,
                           hyd::kCounterbalanceValve, hyd::kPilotCheckValve, hyd::kVariablePump,
                           hyd::kLsValveSection, hyd::kShuttleValve, hyd::kOpenCentreValve);
