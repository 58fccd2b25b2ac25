/* strands_tfx.c - AMD TressFX `.tfx` guide strands (3.x and 4.x layouts)
 * and the follow strands TressFX grows around its guides.
 *
 * 3.x: little-endian; f32 version (< 3.5) at 0; u32 numStrands,
 * numVerticesPerStrand, numFollowStrandsPerGuide, bothEndsImmovable at
 * 4..19; six u32 byte offsets at 144 (vertex positions, thickness, strand
 * UV, colour, guide, vertex UV); a 296-byte header; float3 positions at the
 * first offset, or right after the header when it is 0.
 * 4.x: f32 version (>= 4); u32 numHairStrands, numVerticesPerStrand,
 * offsetVertexPosition, offsetStrandUV, offsetVertexUV,
 * offsetStrandThickness, offsetVertexColor; u32 reserved[32]: a 160-byte
 * header; float4 positions (xyz + inverse mass); offset 0 = absent. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "le_bytes.h"
#include "satf/common.h"
#include "satf/import.h"
#include "satf/math.h"
#include "strands_formats.h"

enum { TFX3_HEADER = 296, TFX3_OFFSETS = 144, TFX4_HEADER = 160 };
#define TFX_MAX_VERTICES 4096

static satf_status check_counts(const char *name, uint32_t strands,
                                uint32_t vertices, satf_error *err) {
  if (strands == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT, "%s: holds no strands", name);
  if (strands > SATF_STRANDS_MAX_STRANDS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd strand count %u (at most %u)", name,
                          strands, SATF_STRANDS_MAX_STRANDS);
  if (vertices < 2)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: %u vertices per strand: strands with no "
                          "segment",
                          name, vertices);
  if (vertices > TFX_MAX_VERTICES)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd %u vertices per strand (at most %d)",
                          name, vertices, TFX_MAX_VERTICES);
  if ((uint64_t)strands * vertices > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd point count %u x %u (at most %u)", name,
                          strands, vertices, SATF_STRANDS_MAX_POINTS);
  return SATF_OK;
}

/* Checks that the optional array at `offset` starts inside the file. */
static satf_status check_offset(const char *name, const char *what,
                                uint32_t offset, uint32_t header, size_t size,
                                satf_error *err) {
  if (offset != 0 && (offset < header || offset > size))
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: the %s offset %u lies outside the data (%u.."
                          "%zu)",
                          name, what, offset, header, size);
  return SATF_OK;
}

/* Copies n points of `stride` floats (xyz first) into a new strand set of
 * equal-length strands, rejecting non-finite coordinates. */
static satf_status positions_to_set(const char *name, const unsigned char *p,
                                    uint32_t strands, uint32_t vertices,
                                    int stride, satf_strand_set **out,
                                    satf_error *err) {
  size_t n = (size_t)strands * vertices;
  float *xyz = malloc(3 * n * sizeof(float));
  int *counts = malloc((size_t)strands * sizeof(int));
  if (!xyz || !counts) {
    free(xyz);
    free(counts);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: cannot hold %zu points",
                          name, n);
  }
  satf_status st = SATF_OK;
  for (size_t k = 0; k < n && st == SATF_OK; k++)
    for (int c = 0; c < 3; c++) {
      float v = lef32(p + 4 * ((size_t)stride * k + (size_t)c));
      if (!isfinite(v)) {
        st = satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: strand %zu vertex %zu is not finite", name,
                            k / vertices, k % vertices);
        break;
      }
      xyz[3 * k + (size_t)c] = v;
    }
  for (uint32_t i = 0; i < strands; i++)
    counts[i] = (int)vertices;
  if (st == SATF_OK)
    st = satf_strand_set_create((int)strands, counts, xyz, NULL, out, err);
  free(xyz);
  free(counts);
  return st;
}

static satf_status parse_v3(const unsigned char *b, size_t size,
                            const char *name, satf_tfx_info *info,
                            satf_strand_set **out, satf_error *err) {
  if (size < TFX3_HEADER)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: truncated header (%zu bytes, a TressFX 3 "
                          "header has %d)",
                          name, size, TFX3_HEADER);
  uint32_t strands = le32(b + 4), vertices = le32(b + 8);
  uint32_t follow = le32(b + 12), ends = le32(b + 16);
  satf_status st = check_counts(name, strands, vertices, err);
  if (st != SATF_OK)
    return st;
  if (follow > SATF_STRANDS_MAX_FOLLOW)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: absurd %u follow strands per guide (at most "
                          "%d)",
                          name, follow, SATF_STRANDS_MAX_FOLLOW);
  static const char *names[6] = {"vertex position", "thickness", "strand UV",
                                 "colour",          "guide",     "vertex UV"};
  uint32_t off[6];
  for (int k = 0; k < 6; k++) {
    off[k] = le32(b + TFX3_OFFSETS + 4 * k);
    st = check_offset(name, names[k], off[k], TFX3_HEADER, size, err);
    if (st != SATF_OK)
      return st;
  }
  uint64_t pos = off[0] ? off[0] : TFX3_HEADER;
  uint64_t need = pos + 12ull * strands * vertices;
  if (need > size)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: truncated: %u strands x %u vertices need %llu "
                          "bytes, the file has %zu",
                          name, strands, vertices, (unsigned long long)need,
                          size);
  if (info) {
    info->guides = (int)strands;
    info->vertices = (int)vertices;
    info->follow_per_guide = (int)follow;
    info->both_ends_immovable = ends != 0;
  }
  return positions_to_set(name, b + pos, strands, vertices, 3, out, err);
}

static satf_status parse_v4(const unsigned char *b, size_t size,
                            const char *name, satf_tfx_info *info,
                            satf_strand_set **out, satf_error *err) {
  if (size < TFX4_HEADER)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: truncated header (%zu bytes, a TressFX 4 "
                          "header has %d)",
                          name, size, TFX4_HEADER);
  uint32_t strands = le32(b + 4), vertices = le32(b + 8);
  satf_status st = check_counts(name, strands, vertices, err);
  if (st != SATF_OK)
    return st;
  static const char *names[5] = {"vertex position", "strand UV", "vertex UV",
                                 "strand thickness", "vertex colour"};
  uint32_t off[5];
  for (int k = 0; k < 5; k++) {
    off[k] = le32(b + 12 + 4 * k);
    st = check_offset(name, names[k], off[k], TFX4_HEADER, size, err);
    if (st != SATF_OK)
      return st;
  }
  if (off[0] == 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: no vertex positions (offset 0)", name);
  uint64_t need = off[0] + 16ull * strands * vertices;
  if (need > size)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: truncated: %u strands x %u vertices need %llu "
                          "bytes, the file has %zu",
                          name, strands, vertices, (unsigned long long)need,
                          size);
  if (info) {
    info->guides = (int)strands;
    info->vertices = (int)vertices;
    info->follow_per_guide = 0;
    info->both_ends_immovable = 0;
  }
  return positions_to_set(name, b + off[0], strands, vertices, 4, out, err);
}

satf_status satf_tfx_parse(const void *data, size_t size, const char *name,
                           satf_tfx_info *info, satf_strand_set **out,
                           satf_error *err) {
  const unsigned char *b = data;
  *out = NULL;
  if (!name)
    name = "<tfx>";
  if (size < 4)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s: truncated header (%zu bytes)", name, size);
  float version = lef32(b);
  if (info) {
    memset(info, 0, sizeof *info);
    info->version = version;
  }
  if (!strands_tfx_version_plausible(version))
    return satf_error_set(
        err, SATF_ERR_FORMAT,
        "%s: unrecognised format; satf reads " STRANDS_FORMATS_READ
        " (it does not begin with a TressFX version)",
        name);
  if (isfinite(version) && version >= 1.0f && version < 3.5f)
    return parse_v3(b, size, name, info, out, err);
  if (isfinite(version) && version >= 4.0f && version < 5.0f)
    return parse_v4(b, size, name, info, out, err);
  return satf_error_set(err, SATF_ERR_VERSION,
                        "%s: TressFX version %g is not supported (3.x or 4.x "
                        "expected)",
                        name, (double)version);
}

satf_status satf_tfx_read(const char *path, satf_tfx_info *info,
                          satf_strand_set **out, satf_error *err) {
  *out = NULL;
  void *buf;
  size_t n;
  satf_status st =
      satf_read_file(path, SATF_STRANDS_MAX_FILE_BYTES, &buf, &n, err);
  if (st == SATF_OK)
    st = satf_tfx_parse(buf, n, path, info, out, err);
  free(buf);
  return st;
}

satf_status satf_tfx_write(const char *path, const satf_strand_set *s,
                           int major_version, int follow_per_guide,
                           satf_error *err) {
  int n = satf_strand_set_count(s), v = satf_strand_set_points(s, 0);
  for (int i = 1; i < n; i++)
    if (satf_strand_set_points(s, i) != v)
      return satf_error_set(err, SATF_ERR_ARGUMENT,
                            "%s: TressFX strands share one vertex count; "
                            "strand %d has %d, strand 0 has %d",
                            path, i, satf_strand_set_points(s, i), v);
  if (major_version != 3 && major_version != 4)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: TressFX version %d (3 or 4)", path,
                          major_version);
  int header = major_version == 3 ? TFX3_HEADER : TFX4_HEADER;
  int stride = major_version == 3 ? 3 : 4;
  size_t size = (size_t)header + 4 * (size_t)stride * n * (size_t)v;
  unsigned char *buf = calloc(1, size);
  if (!buf)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  putf32(buf, major_version == 3 ? 3.0f : 4.0f);
  put32(buf + 4, (uint32_t)n);
  put32(buf + 8, (uint32_t)v);
  if (major_version == 3) {
    put32(buf + 12, (uint32_t)follow_per_guide);
    put32(buf + TFX3_OFFSETS, TFX3_HEADER);
  } else {
    put32(buf + 12, TFX4_HEADER);
  }
  unsigned char *p = buf + header;
  for (int i = 0; i < n; i++) {
    const float *q = satf_strand_set_strand(s, i, NULL);
    for (int k = 0; k < v; k++) {
      for (int c = 0; c < 3; c++, p += 4)
        putf32(p, q[3 * k + c]);
      if (stride == 4) {
        putf32(p, 1.0f);
        p += 4;
      }
    }
  }
  satf_status st = satf_write_file_atomic(path, buf, size, err);
  free(buf);
  return st;
}

/* ---- Follow strands ---------------------------------------------------- */

/* Direction of the guide at vertex k: its outgoing segment (the incoming
 * one at the tip), or the previous direction across repeated points. */
static void guide_tangent(const float *p, int n, int k, const double prev[3],
                          double t[3]) {
  int a = k < n - 1 ? k : n - 2;
  for (int c = 0; c < 3; c++)
    t[c] = (double)p[3 * (a + 1) + c] - p[3 * a + c];
  if (satf_dot3d(t, t) < 1e-24)
    memcpy(t, prev, 3 * sizeof(double));
  satf_normalize3d(t);
}

/* Rotates n by the smallest rotation that turns t0 into t1 (Rodrigues),
 * one step of parallel transport, so the follower does not spin about its
 * guide. */
static void transport(const double t0[3], const double t1[3], double n[3]) {
  double k[3];
  satf_cross3d(t0, t1, k);
  double s = sqrt(satf_dot3d(k, k)), c = satf_dot3d(t0, t1);
  if (s < 1e-12)
    return;
  for (int i = 0; i < 3; i++)
    k[i] /= s;
  double kn[3], kd = satf_dot3d(k, n);
  satf_cross3d(k, n, kn);
  for (int i = 0; i < 3; i++)
    n[i] = n[i] * c + kn[i] * s + k[i] * kd * (1.0 - c);
  double m = satf_dot3d(n, t1);
  for (int i = 0; i < 3; i++)
    n[i] -= m * t1[i];
  satf_normalize3d(n);
}

static void any_perpendicular(const double t[3], double n[3]) {
  double a[3] = {0, 0, 0};
  int k = fabs(t[0]) < fabs(t[1]) ? (fabs(t[0]) < fabs(t[2]) ? 0 : 2)
                                  : (fabs(t[1]) < fabs(t[2]) ? 1 : 2);
  a[k] = 1.0;
  double c[3];
  satf_cross3d(t, a, c);
  satf_cross3d(c, t, n);
  satf_normalize3d(n);
}

satf_status satf_strand_set_add_follow(const satf_strand_set *guides,
                                       const satf_follow_params *p,
                                       satf_strand_set **out, satf_error *err) {
  return satf_strand_set_add_follow_progress(guides, p, NULL, NULL, out, err);
}

satf_status satf_strand_set_add_follow_progress(
    const satf_strand_set *guides, const satf_follow_params *p,
    void (*progress)(void *ctx, size_t done, size_t total), void *progress_ctx,
    satf_strand_set **out, satf_error *err) {
  *out = NULL;
  if (p->count < 0 || p->count > SATF_STRANDS_MAX_FOLLOW ||
      !(p->radius >= 0.0f) || !isfinite(p->radius) ||
      !(p->tip_separation >= 0.0f) || !isfinite(p->tip_separation))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "follow strands: count %d (0..%d), radius %g and "
                          "tip separation %g (finite, >= 0)",
                          p->count, SATF_STRANDS_MAX_FOLLOW, (double)p->radius,
                          (double)p->tip_separation);
  int g = satf_strand_set_count(guides);
  uint64_t n_out = (uint64_t)g * (uint64_t)(p->count + 1);
  uint64_t pts = satf_strand_set_point_count(guides) * (uint64_t)(p->count + 1);
  if (n_out > SATF_STRANDS_MAX_STRANDS || pts > SATF_STRANDS_MAX_POINTS)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "follow strands: %d guides x %d followers is too "
                          "many",
                          g, p->count + 1);
  float *xyz = malloc(3 * (size_t)pts * sizeof(float));
  int *counts = malloc((size_t)n_out * sizeof(int));
  if (!xyz || !counts) {
    free(xyz);
    free(counts);
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "follow strands: cannot hold %llu points",
                          (unsigned long long)pts);
  }
  float *w = xyz;
  int *cw = counts;
  for (int i = 0; i < g; i++) {
    if (progress && (i & 63) == 0)
      progress(progress_ctx, (size_t)i, (size_t)g);
    int n;
    const float *q = satf_strand_set_strand(guides, i, &n);
    memcpy(w, q, 3 * (size_t)n * sizeof(float));
    w += 3 * n;
    *cw++ = n;
    satf_rng rng;
    satf_rng_seed(&rng, p->seed, (uint64_t)i);
    for (int f = 0; f < p->count; f++) {
      double r = p->radius * sqrt(satf_rng_uniform(&rng));
      double phi = 2.0 * SATF_PI * satf_rng_uniform(&rng);
      double ox = r * cos(phi), oy = r * sin(phi);
      double t[3] = {0, 0, 1}, n1[3], n2[3];
      guide_tangent(q, n, 0, t, t);
      any_perpendicular(t, n1);
      for (int k = 0; k < n; k++) {
        if (k > 0) {
          double t1[3];
          guide_tangent(q, n, k, t, t1);
          transport(t, t1, n1);
          memcpy(t, t1, sizeof t);
        }
        satf_cross3d(t, n1, n2);
        double grow = 1.0 + p->tip_separation * (double)k / (double)(n - 1);
        for (int c = 0; c < 3; c++)
          w[3 * k + c] =
              (float)(q[3 * k + c] + grow * (ox * n1[c] + oy * n2[c]));
      }
      w += 3 * n;
      *cw++ = n;
    }
  }
  if (progress)
    progress(progress_ctx, (size_t)g, (size_t)g);
  satf_status st =
      satf_strand_set_create((int)n_out, counts, xyz, NULL, out, err);
  free(xyz);
  free(counts);
  return st;
}

float satf_strand_set_root_spacing(const satf_strand_set *s) {
  int n = satf_strand_set_count(s);
  if (n < 2)
    return 0.0f;
  /* The roots side by side: the scan below streams through them (reaching
   * each root through its strand took 25 s for 0.5 M strands). */
  float *roots = malloc(3 * (size_t)n * sizeof *roots);
  if (roots)
    for (int j = 0; j < n; j++)
      memcpy(roots + 3 * (size_t)j, satf_strand_set_strand(s, j, NULL),
             3 * sizeof *roots);
  /* At most 2000 probe roots keep this O(2000 n). */
  int probes = n < 2000 ? n : 2000;
  double sum = 0.0;
  for (int k = 0; k < probes; k++) {
    int i = (int)((int64_t)k * n / probes);
    const float *a = satf_strand_set_strand(s, i, NULL);
    double best = INFINITY;
    for (int j = 0; j < n; j++) {
      if (j == i)
        continue;
      const float *b =
          roots ? roots + 3 * (size_t)j : satf_strand_set_strand(s, j, NULL);
      double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
      double d = dx * dx + dy * dy + dz * dz;
      if (d < best)
        best = d;
    }
    sum += sqrt(best);
  }
  free(roots);
  return (float)(sum / probes);
}
