/* fuzz_ply.c - libFuzzer target for the PLY strand reader (ascii and binary;
 * strand counts or edges). Compiled into test_strand_formats with
 * SATF_FUZZ_PLY_ENTRY renamed, where the same entry point replays truncations
 * and byte flips of valid files. The bytes also go through format detection,
 * which must never read past them. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "satf/import.h"

#ifndef SATF_FUZZ_PLY_ENTRY
#define SATF_FUZZ_PLY_ENTRY LLVMFuzzerTestOneInput
#endif

int SATF_FUZZ_PLY_ENTRY(const uint8_t *data, size_t size);

int SATF_FUZZ_PLY_ENTRY(const uint8_t *data, size_t size) {
  satf_strand_set *s = NULL;
  satf_error err;
  (void)satf_strands_detect(data, size);
  if (satf_ply_parse(data, size, "fuzz.ply", &s, &err) == SATF_OK) {
    /* a set that loads must be usable: every strand has a segment */
    float lo[3], hi[3];
    satf_strand_set_bounds(s, lo, hi);
    for (int i = 0; i < satf_strand_set_count(s); i++)
      if (satf_strand_set_points(s, i) < 2)
        abort();
    satf_strand_set_destroy(s);
  } else if (err.message[0] == '\0' || s != NULL) {
    abort(); /* every failure must say why and return nothing */
  }
  return 0;
}
