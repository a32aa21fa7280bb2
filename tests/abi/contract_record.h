/* One entry of the ABI's contract as one set of headers compiles it: a
 * struct's size and alignment, a field's offset, size and alignment, an
 * integer constant's value or a string constant's text. The same list
 * (sdk-3.0/contract.def) is compiled twice, against the frozen 3.0 headers
 * (sdk-3.0/frozen_contract.c) and against the SDK's own (current_contract.c),
 * and frozen_contract_test.cpp compares the two tables. */
#ifndef MH_TESTS_ABI_CONTRACT_RECORD_H
#define MH_TESTS_ABI_CONTRACT_RECORD_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mh_abi_record_kind {
  MH_ABI_RECORD_STRUCT = 0,
  MH_ABI_RECORD_FIELD = 1,
  MH_ABI_RECORD_INTEGER = 2,
  MH_ABI_RECORD_STRING = 3
} mh_abi_record_kind;

typedef struct mh_abi_record {
  mh_abi_record_kind kind;
  const char* owner;        /* the struct of a field; NULL otherwise */
  const char* name;         /* the struct, field or constant */
  size_t offset;            /* a field's */
  size_t size;              /* a struct's or a field's */
  size_t align;             /* a struct's or a field's */
  unsigned long long value; /* an integer constant's */
  const char* text;         /* a string constant's */
} mh_abi_record;

/* The table as the frozen 3.0 headers give it, and its version. */
extern const mh_abi_record mh_abi_frozen[];
extern const size_t mh_abi_frozen_count;
extern const unsigned mh_abi_frozen_major, mh_abi_frozen_minor;
/* The table as the SDK's headers give it today, and their version. */
extern const mh_abi_record mh_abi_current[];
extern const size_t mh_abi_current_count;
extern const unsigned mh_abi_current_major, mh_abi_current_minor;

#ifdef __cplusplus
}
#endif

#endif
