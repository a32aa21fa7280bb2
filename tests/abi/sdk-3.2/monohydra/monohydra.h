/* monohydra SDK: everything a plugin needs. */
#ifndef MONOHYDRA_H
#define MONOHYDRA_H
#include "monohydra/entry.h"
#include "monohydra/formulation.h"
#include "monohydra/host.h"
#include "monohydra/integrator.h"
#include "monohydra/state.h"
#include "monohydra/subsystem.h"
#include "monohydra/types.h"
#endif
