/* strands_hair.c - the strand set (satf/strands.h) and Cem Yuksel's cyHair
 * `.hair` format: a 128-byte header ("HAIR", counts, a bit set of the
 * arrays present, defaults) followed by the arrays present, in order:
 * u16 segments[hairs], f32 points[3 * points], f32 thickness[points],
 * f32 transparency[points], f32 colours[3 * points]. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "le_bytes.h"
#include "satf/common.h"
#include "satf/import.h"
#include "strands_read.h"

struct satf_strand_set {
  int n;
  size_t *offset; /* n + 1 point offsets */
  float *points;  /* 3 per point */
  float *thickness;
  float *colour; /* 3 per point, or NULL */
};

enum {
  HAIR_HEADER = 128,
  HAIR_SEGMENTS = 1,
  HAIR_POINTS = 2,
  HAIR_THICKNESS = 4,
  HAIR_TRANSPARENCY = 8,
  HAIR_COLORS = 16
};

static satf_status set_alloc(int n, size_t n_points, int with_thickness,
                             satf_strand_set **out, satf_error *err) {
  *out = NULL;
  satf_strand_set *s = calloc(1, sizeof *s);
  if (!s)
    return satf_error_set(err, SATF_ERR_NOMEM, "strand set: out of memory");
  s->n = n;
  s->offset = malloc(((size_t)n + 1) * sizeof *s->offset);
  s->points = malloc((n_points ? n_points : 1) * 3 * sizeof(float));
  if (with_thickness)
    s->thickness = malloc((n_points ? n_points : 1) * sizeof(float));
  if (!s->offset || !s->points || (with_thickness && !s->thickness)) {
    satf_strand_set_destroy(s);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "strand set: cannot allocate %d strands of %zu "
                          "points",
                          n, n_points);
  }
  s->offset[0] = 0;
  *out = s;
  return SATF_OK;
}

satf_status satf_strand_set_create(int n_strands, const int *counts,
                                   const float *points, const float *thickness,
                                   satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (n_strands < 1 || (unsigned)n_strands > SATF_STRANDS_MAX_STRANDS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strand set: %d strands is out of range [1, %u]",
                          n_strands, SATF_STRANDS_MAX_STRANDS);
  size_t total = 0;
  for (int i = 0; i < n_strands; i++) {
    if (counts[i] < 2 || counts[i] > SATF_STRANDS_MAX_PER_STRAND)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strand set: strand %d has %d points (a strand "
                            "needs 2..%d)",
                            i, counts[i], SATF_STRANDS_MAX_PER_STRAND);
    total += (size_t)counts[i];
  }
  if (total > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strand set: %zu points is absurd (at most %u)",
                          total, SATF_STRANDS_MAX_POINTS);
  for (size_t k = 0; k < 3 * total; k++)
    if (!isfinite(points[k]))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strand set: point %zu is not finite", k / 3);
  satf_strand_set *s;
  satf_status st = set_alloc(n_strands, total, thickness != NULL, &s, err);
  if (st != SATF_OK)
    return st;
  for (int i = 0; i < n_strands; i++)
    s->offset[i + 1] = s->offset[i] + (size_t)counts[i];
  memcpy(s->points, points, 3 * total * sizeof(float));
  if (thickness)
    memcpy(s->thickness, thickness, total * sizeof(float));
  *out = s;
  return SATF_OK;
}

void satf_strand_set_destroy(satf_strand_set *s) {
  if (s) {
    free(s->offset);
    free(s->points);
    free(s->thickness);
    free(s->colour);
    free(s);
  }
}

satf_status satf_strand_set_concat(const satf_strand_set *a,
                                   const satf_strand_set *b,
                                   satf_strand_set **out, satf_error *err) {
  *out = NULL;
  size_t na = a->offset[a->n], nb = b->offset[b->n];
  if ((size_t)a->n + (size_t)b->n > SATF_STRANDS_MAX_STRANDS ||
      na + nb > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "strand set: %d + %d strands is too many", a->n,
                          b->n);
  satf_strand_set *s;
  int thick = a->thickness && b->thickness;
  satf_status st = set_alloc(a->n + b->n, na + nb, thick, &s, err);
  if (st != SATF_OK)
    return st;
  memcpy(s->offset, a->offset, ((size_t)a->n + 1) * sizeof *s->offset);
  for (int i = 1; i <= b->n; i++)
    s->offset[a->n + i] = na + b->offset[i];
  memcpy(s->points, a->points, 3 * na * sizeof(float));
  memcpy(s->points + 3 * na, b->points, 3 * nb * sizeof(float));
  if (thick) {
    memcpy(s->thickness, a->thickness, na * sizeof(float));
    memcpy(s->thickness + na, b->thickness, nb * sizeof(float));
  }
  if (a->colour && b->colour) {
    if (!(s->colour = malloc(3 * (na + nb) * sizeof(float)))) {
      satf_strand_set_destroy(s);
      return satf_error_set(err, SATF_ERR_NOMEM, "strand set: out of memory");
    }
    memcpy(s->colour, a->colour, 3 * na * sizeof(float));
    memcpy(s->colour + 3 * na, b->colour, 3 * nb * sizeof(float));
  }
  *out = s;
  return SATF_OK;
}

int satf_strand_set_count(const satf_strand_set *s) { return s->n; }

size_t satf_strand_set_point_count(const satf_strand_set *s) {
  return s->offset[s->n];
}

const float *satf_strand_set_strand(const satf_strand_set *s, int i,
                                    int *n_points) {
  if (n_points)
    *n_points = (int)(s->offset[i + 1] - s->offset[i]);
  return s->points + 3 * s->offset[i];
}

int satf_strand_set_points(const satf_strand_set *s, int i) {
  return (int)(s->offset[i + 1] - s->offset[i]);
}

const float *satf_strand_set_thickness(const satf_strand_set *s, int i) {
  return s->thickness ? s->thickness + s->offset[i] : NULL;
}

const float *satf_strand_set_colour(const satf_strand_set *s, int i) {
  return s->colour ? s->colour + 3 * s->offset[i] : NULL;
}

satf_status satf_strand_set_add_colour(satf_strand_set *s, const float *rgb,
                                       satf_error *err) {
  size_t n = 3 * s->offset[s->n];
  for (size_t k = 0; k < n; k++)
    if (!isfinite(rgb[k]))
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "strand set: the colour of point %zu is not "
                            "finite",
                            k / 3);
  float *c = malloc((n ? n : 1) * sizeof(float));
  if (!c)
    return satf_error_set(err, SATF_ERR_NOMEM, "strand set: out of memory");
  memcpy(c, rgb, n * sizeof(float));
  free(s->colour);
  s->colour = c;
  return SATF_OK;
}

void satf_strand_set_bounds(const satf_strand_set *s, float lo[3],
                            float hi[3]) {
  for (int c = 0; c < 3; c++) {
    lo[c] = FLT_MAX;
    hi[c] = -FLT_MAX;
  }
  for (size_t k = 0; k < s->offset[s->n]; k++)
    for (int c = 0; c < 3; c++) {
      float v = s->points[3 * k + c];
      lo[c] = v < lo[c] ? v : lo[c];
      hi[c] = v > hi[c] ? v : hi[c];
    }
}

float satf_strand_set_length(const satf_strand_set *s, int i) {
  int n;
  const float *p = satf_strand_set_strand(s, i, &n);
  double len = 0.0;
  for (int k = 1; k < n; k++) {
    double dx = p[3 * k] - p[3 * k - 3], dy = p[3 * k + 1] - p[3 * k - 2],
           dz = p[3 * k + 2] - p[3 * k - 1];
    len += sqrt(dx * dx + dy * dy + dz * dz);
  }
  return (float)len;
}

/* ---- cyHair ------------------------------------------------------------ */

/* The byte size the header promises, in 64 bits so absurd counts cannot
 * wrap. */
static uint64_t hair_expected_size(uint32_t flags, uint64_t hairs,
                                   uint64_t points) {
  uint64_t size = HAIR_HEADER;
  if (flags & HAIR_SEGMENTS)
    size += 2 * hairs;
  if (flags & HAIR_POINTS)
    size += 12 * points;
  if (flags & HAIR_THICKNESS)
    size += 4 * points;
  if (flags & HAIR_TRANSPARENCY)
    size += 4 * points;
  if (flags & HAIR_COLORS)
    size += 12 * points;
  return size;
}

static satf_status check_finite_array(const unsigned char *p, uint64_t n,
                                      const char *name, const char *what,
                                      satf_error *err) {
  for (uint64_t k = 0; k < n; k++)
    if (!isfinite(lef32(p + 4 * k)))
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: %s value %llu is not finite", name, what,
                            (unsigned long long)k);
  return SATF_OK;
}

/* True when the header's defaults are the values cyHair's own writer
 * (cyHairFile.h, InitHeader) starts from: thickness 1, transparency 0,
 * colour white. A file with no thickness array and these defaults never
 * set a thickness: Bangs_100, whose 1.0 would draw each strand 2.7 times a
 * fibre's width at its scale. Such a file gives no thickness, and the
 * importer's fibre default applies. */
static int hair_defaults_unset(const unsigned char *b) {
  return lef32(b + 20) == 1.0f && lef32(b + 24) == 0.0f &&
         lef32(b + 28) == 1.0f && lef32(b + 32) == 1.0f &&
         lef32(b + 36) == 1.0f;
}

satf_status satf_hair_parse(const void *data, size_t size, const char *name,
                            satf_strand_set **out, satf_error *err) {
  const unsigned char *b = data;
  *out = NULL;
  if (!name)
    name = "<hair>";
  if (size < HAIR_HEADER)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: truncated header (%zu bytes, a .hair header "
                          "has 128)",
                          name, size);
  if (memcmp(b, "HAIR", 4) != 0)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: not a cyHair file (no \"HAIR\" signature)",
                          name);
  uint32_t hairs = le32(b + 4), points = le32(b + 8), flags = le32(b + 12);
  uint32_t def_segments = le32(b + 16);
  float def_thickness = lef32(b + 20);
  if (hairs == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: holds no strands", name);
  if (hairs > SATF_STRANDS_MAX_STRANDS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd strand count %u (at most %u)", name,
                          hairs, SATF_STRANDS_MAX_STRANDS);
  if (points > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd point count %u (at most %u)", name,
                          points, SATF_STRANDS_MAX_POINTS);
  if (!(flags & HAIR_POINTS))
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: the arrays flags (0x%x) say the file has no "
                          "points array",
                          name, flags);
  if (flags & ~0x1Fu)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: unknown bits in the arrays flags 0x%x", name,
                          flags);
  uint64_t expect = hair_expected_size(flags, hairs, points);
  if (size < expect)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: truncated: %zu bytes, but the header promises "
                          "%llu (%u strands, %u points)",
                          name, size, (unsigned long long)expect, hairs,
                          points);
  if (2ull * hairs > points)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: counts do not add up: %u strands need at least "
                          "%llu points, the header says %u",
                          name, hairs, 2ull * hairs, points);
  const unsigned char *seg = b + HAIR_HEADER;
  const unsigned char *pts = seg + ((flags & HAIR_SEGMENTS) ? 2ull * hairs : 0);
  const unsigned char *thick = pts + 12ull * points;
  /* after the thickness and transparency arrays present */
  const unsigned char *rgb = thick +
                             ((flags & HAIR_THICKNESS) ? 4ull * points : 0) +
                             ((flags & HAIR_TRANSPARENCY) ? 4ull * points : 0);
  /* Counts must add up before anything is allocated. */
  uint64_t sum = 0;
  for (uint32_t i = 0; i < hairs; i++) {
    uint32_t s = (flags & HAIR_SEGMENTS)
                     ? (uint32_t)seg[2 * i] | (uint32_t)seg[2 * i + 1] << 8
                     : def_segments;
    if (s == 0)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: strand %u has no segment", name, i);
    if (s + 1 > SATF_STRANDS_MAX_PER_STRAND)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: strand %u has an absurd %u segments", name, i,
                            s);
    sum += s + 1;
    if (sum > points)
      break; /* already too many: no need to read on */
  }
  if (sum != points)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: counts do not add up: the strands' segments "
                          "need %llu points, the header says %u",
                          name, (unsigned long long)sum, points);
  satf_status st = check_finite_array(pts, 3ull * points, name, "point", err);
  if (st == SATF_OK && (flags & HAIR_THICKNESS))
    st = check_finite_array(thick, points, name, "thickness", err);
  if (st == SATF_OK && (flags & HAIR_COLORS))
    st = check_finite_array(rgb, 3ull * points, name, "colour", err);
  if (st != SATF_OK)
    return st;
  satf_strand_set *s;
  st = set_alloc((int)hairs, points, 1, &s, err);
  if (st != SATF_OK)
    return st;
  for (uint32_t i = 0; i < hairs; i++) {
    uint32_t n = (flags & HAIR_SEGMENTS)
                     ? (uint32_t)seg[2 * i] | (uint32_t)seg[2 * i + 1] << 8
                     : def_segments;
    s->offset[i + 1] = s->offset[i] + n + 1;
  }
  for (uint64_t k = 0; k < 3ull * points; k++)
    s->points[k] = lef32(pts + 4 * k);
  for (uint64_t k = 0; k < points; k++)
    s->thickness[k] =
        (flags & HAIR_THICKNESS) ? lef32(thick + 4 * k) : def_thickness;
  if (!(flags & HAIR_THICKNESS) &&
      (!isfinite(def_thickness) || hair_defaults_unset(b))) {
    free(s->thickness);
    s->thickness = NULL;
  }
  /* the colours kept as given (exporters write linear RGB, cyHair says no
   * more); the scene's material decides how the hair is lit */
  if ((flags & HAIR_COLORS) &&
      !(s->colour = malloc(3ull * points * sizeof(float)))) {
    satf_strand_set_destroy(s);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  }
  for (uint64_t k = 0; s->colour && k < 3ull * points; k++)
    s->colour[k] = lef32(rgb + 4 * k);
  *out = s;
  return SATF_OK;
}

satf_status satf_hair_read(const char *path, satf_strand_set **out,
                           satf_error *err) {
  return strands_read_file(path, satf_hair_parse, out, err);
}

satf_status satf_hair_write(const char *path, const satf_strand_set *s,
                            satf_error *err) {
  size_t points = s->offset[s->n];
  for (int i = 0; i < s->n; i++)
    if (satf_strand_set_points(s, i) - 1 > 65535)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: strand %d has more segments than a .hair "
                            "file holds (65535)",
                            path, i);
  uint32_t flags = HAIR_SEGMENTS | HAIR_POINTS;
  if (s->thickness)
    flags |= HAIR_THICKNESS;
  if (s->colour)
    flags |= HAIR_COLORS;
  size_t size = (size_t)hair_expected_size(flags, (uint64_t)s->n, points);
  unsigned char *buf = calloc(1, size);
  if (!buf)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  memcpy(buf, "HAIR", 4);
  put32(buf + 4, (uint32_t)s->n);
  put32(buf + 8, (uint32_t)points);
  put32(buf + 12, flags);
  put32(buf + 16, 0);
  /* cyHair's initial defaults (thickness 1, transparency 0, colour white):
   * a set without thickness reads back without it */
  putf32(buf + 20, 1.0f);
  putf32(buf + 24, 0.0f);
  for (int c = 0; c < 3; c++)
    putf32(buf + 28 + 4 * c, 1.0f);
  snprintf((char *)buf + 40, 88, "written by satf %s", SATF_VERSION_STRING);
  unsigned char *p = buf + HAIR_HEADER;
  for (int i = 0; i < s->n; i++) {
    uint32_t seg = (uint32_t)satf_strand_set_points(s, i) - 1;
    p[0] = (unsigned char)seg;
    p[1] = (unsigned char)(seg >> 8);
    p += 2;
  }
  for (size_t k = 0; k < 3 * points; k++, p += 4)
    putf32(p, s->points[k]);
  if (s->thickness)
    for (size_t k = 0; k < points; k++, p += 4)
      putf32(p, s->thickness[k]);
  if (s->colour)
    for (size_t k = 0; k < 3 * points; k++, p += 4)
      putf32(p, s->colour[k]);
  satf_status st = satf_write_file_atomic(path, buf, size, err);
  free(buf);
  return st;
}
