/* The sizes and offsets of the frozen SDK 2.0 headers (tests/abi/sdk-2.0),
 * compiled as C11 against them alone, so abi_layout_test.cpp can check that
 * the shipped SDK only appended to them. */
#include <stddef.h>

#include "monohydra/monohydra.h"

#if MH_ABI_VERSION_MAJOR != 2 || MH_ABI_VERSION_MINOR != 0
#error "abi_layout_sdk20.c must see the frozen 2.0 headers"
#endif

const size_t mh_sdk20_sizeof_host = sizeof(mh_host);
const size_t mh_sdk20_sizeof_subsystem = sizeof(mh_subsystem);
const size_t mh_sdk20_sizeof_formulation = sizeof(mh_formulation);
const size_t mh_sdk20_sizeof_integrator = sizeof(mh_integrator);
const size_t mh_sdk20_sizeof_subsystem_factory = sizeof(mh_subsystem_factory);
const size_t mh_sdk20_offset_host_evaluate = offsetof(mh_host, evaluate_mechanics);
const size_t mh_sdk20_offset_subsystem_get_extension = offsetof(mh_subsystem, get_extension);
