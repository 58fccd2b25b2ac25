/* fuzz_data.c - libFuzzer target for the USC-HairSalon .data reader. Compiled
 * into test_strand_formats with SATF_FUZZ_DATA_ENTRY renamed, where the same
 * entry point replays truncations and byte flips of valid files. The bytes
 * also go through format detection, which must never read past them. */
#include <stddef.h>
#include <stdint.h>

#include "fuzz_strands.h"

#ifndef SATF_FUZZ_DATA_ENTRY
#define SATF_FUZZ_DATA_ENTRY LLVMFuzzerTestOneInput
#endif

int SATF_FUZZ_DATA_ENTRY(const uint8_t *data, size_t size);

int SATF_FUZZ_DATA_ENTRY(const uint8_t *data, size_t size) {
  return fuzz_strands_one(data, size, satf_usc_parse, "fuzz.data");
}
