/* fuzz_vdb.c - libFuzzer target for satf_vdb_read. An input is a list of
 * edits to a small valid .vdb written by the shim, so that every input is
 * close to a file OpenVDB reads and the fuzzer spends its time in the voxel
 * data, not on the magic number: 4-byte records (a 24-bit little-endian
 * offset, taken modulo the file size, and a byte to xor there), then, when 3
 * bytes remain, a 24-bit length to cut the file to. Compiled into test_vdb
 * with SATF_FUZZ_VDB_ENTRY renamed, where the same entry point replays byte
 * flips and truncations. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "satf/common.h"
#include "satf/density.h"

#ifndef SATF_FUZZ_VDB_ENTRY
#define SATF_FUZZ_VDB_ENTRY LLVMFuzzerTestOneInput
#endif

int SATF_FUZZ_VDB_ENTRY(const uint8_t *data, size_t size);
const unsigned char *fuzz_vdb_base(size_t *size);

static const char *temp_dir(void) {
  const char *dir = getenv("SATF_TEST_TMP");
  if (!dir)
    dir = getenv("TMPDIR");
  return dir ? dir : "/tmp";
}

/* One Gaussian (mass 2.5, sigma 0.1) on voxels of 0.1: about 77 KB, whose
 * last 2 KB are blosc-compressed leaf buffers. Built once per process. */
const unsigned char *fuzz_vdb_base(size_t *size) {
  static unsigned char *base;
  static size_t base_size;
  if (!base) {
    char path[1024];
    snprintf(path, sizeof path, "%s/satf-fuzz-vdb-base-%ld.vdb", temp_dir(),
             (long)getpid());
    satf_vdb_builder *b = NULL;
    satf_error err;
    const float c[3] = {0.13f, -0.21f, 0.07f};
    void *data = NULL;
    if (satf_vdb_builder_create(0.1f, &b, &err) != SATF_OK ||
        satf_vdb_builder_add_gaussian(b, c, 0.1f, 2.5f, &err) != SATF_OK ||
        satf_vdb_builder_write(b, path, "density", &err) != SATF_OK ||
        satf_read_file(path, 1 << 24, &data, &base_size, &err) != SATF_OK) {
      fprintf(stderr, "fuzz_vdb: cannot build the base file: %s\n",
              err.message);
      abort();
    }
    satf_vdb_builder_destroy(b);
    remove(path);
    base = data;
  }
  *size = base_size;
  return base;
}

static size_t u24(const uint8_t *p) {
  return (size_t)p[0] | (size_t)p[1] << 8 | (size_t)p[2] << 16;
}

/* A grid that loads must be usable everywhere the renderer touches it. */
static void use_grid(const satf_vdb_grid *g) {
  float lo[3], hi[3], d[4];
  const float pts[12] = {0.13f, -0.21f, 0.07f, 0.0f, 0.0f, 0.0f,
                         0.2f,  -0.1f,  0.1f,  1e6f, 0.0f, 0.0f};
  satf_vdb_bbox(g, lo, hi);
  satf_vdb_sample_many(g, 4, pts, d);
  if (satf_vdb_total_mass(g) != satf_vdb_total_mass(g) ||
      !(satf_vdb_voxel_size(g) > 0.0f))
    abort(); /* NaN mass or a degenerate transform got through */
}

int SATF_FUZZ_VDB_ENTRY(const uint8_t *data, size_t size) {
  size_t n;
  const unsigned char *base = fuzz_vdb_base(&n);
  unsigned char *file = malloc(n);
  if (!file)
    return 0;
  memcpy(file, base, n);
  size_t i = 0, len = n;
  for (; i + 4 <= size; i += 4)
    file[u24(data + i) % n] ^= data[i + 3];
  if (size - i == 3)
    len = u24(data + i) % (n + 1);
  char path[1024];
  snprintf(path, sizeof path, "%s/satf-fuzz-vdb-%ld.vdb", temp_dir(),
           (long)getpid());
  FILE *f = fopen(path, "wb");
  if (!f || fwrite(file, 1, len, f) != len || fclose(f) != 0)
    abort();
  free(file);
  satf_vdb_grid *g = NULL;
  satf_error err;
  satf_error_clear(&err);
  if (satf_vdb_read(path, "density", &g, &err) == SATF_OK) {
    use_grid(g);
    satf_vdb_grid_destroy(g);
  } else if (g != NULL || !strstr(err.message, path)) {
    abort(); /* every failure names the file and returns nothing */
  }
  remove(path);
  return 0;
}
