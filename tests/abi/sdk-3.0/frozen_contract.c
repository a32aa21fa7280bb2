/* The 3.0 contract (contract.def) as the frozen 3.0 headers beside this file
 * compile it. Built with this folder alone on its include path
 * (tests/CMakeLists.txt), so "monohydra/..." can only be the frozen copy. */
#include <stddef.h>

#include "../contract_record.h"
#include "monohydra/monohydra.h"

const mh_abi_record mh_abi_frozen[] = {
#include "../contract_table.inc"
};
const size_t mh_abi_frozen_count = sizeof(mh_abi_frozen) / sizeof(mh_abi_frozen[0]);
const unsigned mh_abi_frozen_major = MH_ABI_VERSION_MAJOR;
const unsigned mh_abi_frozen_minor = MH_ABI_VERSION_MINOR;
