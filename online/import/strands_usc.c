/* strands_usc.c - the USC-HairSalon `.data` layout (Hu et al. 2015's
 * database of 343 hairstyles): little-endian int32 strand count, then per
 * strand an int32 point count and float32 x, y, z per point. The dataset
 * marks scalp positions without hair by strands of one point (and
 * sometimes none); its own loader skips them, and so does this reader. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "le_bytes.h"
#include "satf/common.h"
#include "satf/import.h"
#include "strands_read.h"

/* Walks the records without allocating: every count checked against the
 * bytes left; *kept and *points count the strands of two or more points. */
static satf_status usc_scan(const unsigned char *b, size_t size,
                            const char *name, uint32_t n, int *kept,
                            uint64_t *points, satf_error *err) {
  size_t at = 4;
  *kept = 0;
  *points = 0;
  for (uint32_t i = 0; i < n; i++) {
    if (size - at < 4)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: truncated: strand %u of %u has no point "
                            "count",
                            name, i, n);
    int32_t m = (int32_t)le32(b + at);
    at += 4;
    if (m < 0 || m > SATF_STRANDS_MAX_PER_STRAND)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: strand %u has an absurd %d points (at most "
                            "%d)",
                            name, i, m, SATF_STRANDS_MAX_PER_STRAND);
    if ((size - at) / 12 < (size_t)m)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: truncated: strand %u needs %d points, %zu "
                            "bytes are left",
                            name, i, m, size - at);
    for (size_t k = 0; k < 3 * (size_t)m; k++)
      if (!isfinite(lef32(b + at + 4 * k)))
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "%s: strand %u: point %zu is not finite", name, i,
                              k / 3);
    at += 12 * (size_t)m;
    if (m >= 2) {
      (*kept)++;
      *points += (uint64_t)m;
    }
  }
  if (at != size)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: %zu bytes after the last of its %u strands",
                          name, size - at, n);
  if (*kept == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: holds no strand of two or more points", name);
  if (*points > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd point count %llu (at most %u)", name,
                          (unsigned long long)*points, SATF_STRANDS_MAX_POINTS);
  return SATF_OK;
}

satf_status satf_usc_parse(const void *data, size_t size, const char *name,
                           satf_strand_set **out, satf_error *err) {
  const unsigned char *b = data;
  *out = NULL;
  if (!name)
    name = "<data>";
  if (size < 4)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: truncated: %zu bytes, not even a strand count",
                          name, size);
  int32_t n = (int32_t)le32(b);
  if (n <= 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: strand count %d: holds no strands", name, n);
  /* every strand needs at least its 4-byte count */
  if ((uint64_t)n > SATF_STRANDS_MAX_STRANDS || (uint64_t)n * 4 > size - 4)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd strand count %d for %zu bytes", name, n,
                          size);
  int kept;
  uint64_t points;
  satf_status st = usc_scan(b, size, name, (uint32_t)n, &kept, &points, err);
  if (st != SATF_OK)
    return st;
  int *counts = malloc((size_t)kept * sizeof(int));
  float *pts = malloc(3 * (size_t)points * sizeof(float));
  if (!counts || !pts) {
    free(counts);
    free(pts);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: cannot hold %llu points",
                          name, (unsigned long long)points);
  }
  size_t at = 4, to = 0;
  int j = 0;
  for (int32_t i = 0; i < n; i++) {
    int32_t m = (int32_t)le32(b + at);
    at += 4;
    if (m >= 2) {
      counts[j++] = m;
      for (size_t k = 0; k < 3 * (size_t)m; k++)
        pts[to++] = lef32(b + at + 4 * k);
    }
    at += 12 * (size_t)m;
  }
  satf_error why;
  st = satf_strand_set_create(kept, counts, pts, NULL, out, &why);
  if (st != SATF_OK)
    satf_error_set(err, st, "%s: %s", name, why.message);
  free(counts);
  free(pts);
  return st;
}

satf_status satf_usc_read(const char *path, satf_strand_set **out,
                          satf_error *err) {
  return strands_read_file(path, satf_usc_parse, out, err);
}
