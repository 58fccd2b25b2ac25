/* fuzz_db.c - libFuzzer target for the HRIR database reader. With
 * SATF_FUZZ_NO_MAIN it is compiled into test_db_file, which replays
 * truncations and byte flips through the same entry point. */
#define _POSIX_C_SOURCE 200809L
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "satf/db.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char path[64];
  snprintf(path, sizeof path, "/tmp/satf-fuzz-db-%ld.exr", (long)getpid());
  FILE *f = fopen(path, "wb");
  if (!f)
    return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  satf_db *db = NULL;
  satf_error err;
  if (satf_db_read(path, &db, &err) == SATF_OK) {
    /* a file that loads must be usable */
    float re[4096], al[4096];
    if (satf_db_width(db) <= 4096)
      satf_db_lookup(db, satf_db_features(db, 0), 0.3f, 1.1f, 2, re, al);
    satf_db_destroy(db);
  } else if (err.message[0] == '\0') {
    abort(); /* every failure must say why */
  }
  remove(path);
  return 0;
}
