/* fuzz_obj.c - libFuzzer target for the OBJ polyline reader. Compiled into
 * test_strand_real with SATF_FUZZ_OBJ_ENTRY renamed, where the same entry
 * point replays truncations and byte flips of valid files. The bytes also
 * go through format detection, which must never read past them. */
#include <stddef.h>
#include <stdint.h>

#include "fuzz_strands.h"

#ifndef SATF_FUZZ_OBJ_ENTRY
#define SATF_FUZZ_OBJ_ENTRY LLVMFuzzerTestOneInput
#endif

int SATF_FUZZ_OBJ_ENTRY(const uint8_t *data, size_t size);

int SATF_FUZZ_OBJ_ENTRY(const uint8_t *data, size_t size) {
  return fuzz_strands_one(data, size, satf_obj_parse, "fuzz.obj");
}
