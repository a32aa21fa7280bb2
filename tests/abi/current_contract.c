/* The 3.0 contract (sdk-3.0/contract.def) as the SDK's headers compile it
 * today: frozen_contract_test.cpp holds it against the frozen headers'. */
#include <stddef.h>

#include "contract_record.h"
#include "monohydra/monohydra.h"

const mh_abi_record mh_abi_current[] = {
#include "contract_table.inc"
};
const size_t mh_abi_current_count = sizeof(mh_abi_current) / sizeof(mh_abi_current[0]);
const unsigned mh_abi_current_major = MH_ABI_VERSION_MAJOR;
const unsigned mh_abi_current_minor = MH_ABI_VERSION_MINOR;
