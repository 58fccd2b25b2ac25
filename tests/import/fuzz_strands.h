/* fuzz_strands.h - the body every strand-format fuzz target shares: the
 * bytes go through format detection (which must never read past them) and
 * one parser; a set that loads must be usable, and a failure must say why
 * and return nothing. abort() is what libFuzzer and the replays catch. */
#ifndef SATF_TESTS_FUZZ_STRANDS_H
#define SATF_TESTS_FUZZ_STRANDS_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "satf/import.h"

typedef satf_status (*fuzz_strands_parse)(const void *data, size_t size,
                                          const char *name,
                                          satf_strand_set **out,
                                          satf_error *err);

static inline int fuzz_strands_one(const uint8_t *data, size_t size,
                                   fuzz_strands_parse parse, const char *name) {
  satf_strand_set *s = NULL;
  satf_error err;
  (void)satf_strands_detect(data, size);
  if (parse(data, size, name, &s, &err) == SATF_OK) {
    float lo[3], hi[3];
    satf_strand_set_bounds(s, lo, hi);
    for (int i = 0; i < satf_strand_set_count(s); i++)
      if (satf_strand_set_points(s, i) < 2)
        abort();
    satf_strand_set_destroy(s);
  } else if (err.message[0] == '\0' || s != NULL) {
    abort();
  }
  return 0;
}

#endif
