/* hrir_db.c - the in-memory HRIR database and the SATF look-up (eq. 4). */
#include "hrir_db_internal.h"
#include "satf/math.h"

#include <Imath/half.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

satf_status satf_build_params_check(const satf_build_params *p,
                                    satf_error *err) {
  if (p->samples < 1 || p->samples > 1000000)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "samples = %d is out of range [1, 1000000]",
                          p->samples);
  if (p->n_view < 1 || p->n_view > 1024 || p->n_light < 1 || p->n_light > 1024)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "angles %d x %d out of range [1, 1024]", p->n_view,
                          p->n_light);
  if (p->grid < 4 || p->grid > 1024)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "grid = %d is out of range [4, 1024]", p->grid);
  satf_status st = satf_sector_shape_check(&p->shape, err);
  if (st == SATF_OK)
    st = satf_trace_params_check(&p->trace, err);
  if (st == SATF_OK && p->kind != SATF_RECORD_PHONG &&
      p->kind != SATF_RECORD_FIBER)
    st = satf_error_set(err, SATF_ERR_ARGUMENT, "record kind %d is unknown",
                        (int)p->kind);
  if (st == SATF_OK && p->kind == SATF_RECORD_FIBER)
    st = satf_fiber_trace_params_check(&p->fiber, err);
  if (st != SATF_OK)
    return st;
  /* The channels of 4-byte floats in memory; refuse what cannot fit. */
  double bytes = 4.0 * satf_build_params_channels(p) * p->samples *
                 (double)p->n_view * p->n_light * p->trace.width;
  if (bytes > 16e9)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "a database of %d samples x %d x %d angles x %d "
                          "width needs %.1f GB of memory; refusing",
                          p->samples, p->n_view, p->n_light, p->trace.width,
                          bytes / 1e9);
  return SATF_OK;
}

/* Every channel of every record of one sample. */
static size_t values_per_sample(const satf_build_params *p) {
  return (size_t)satf_build_params_channels(p) * (size_t)p->n_view *
         (size_t)p->n_light * (size_t)p->trace.width;
}

satf_status satf_db_create(const satf_build_params *p, satf_db **out,
                           satf_error *err) {
  *out = NULL;
  satf_status st = satf_build_params_check(p, err);
  if (st != SATF_OK)
    return st;
  satf_db *db = calloc(1, sizeof *db);
  if (!db)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate a database");
  db->p = *p;
  size_t n = values_per_sample(p) * (size_t)p->samples;
  db->rec = calloc(n, sizeof(float));
  db->features = calloc((size_t)p->samples * SATF_FEATURES, sizeof(float));
  if (!db->rec || !db->features) {
    satf_db_destroy(db);
    return satf_error_set(
        err, SATF_ERR_NOMEM, "cannot allocate %zu records of %d samples",
        n / values_per_sample(p) * (size_t)p->n_view * (size_t)p->n_light,
        p->trace.width);
  }
  *out = db;
  return SATF_OK;
}

satf_status satf_db_adopt(const satf_build_params *p, float *rec,
                          float *features, satf_db **out, satf_error *err) {
  satf_db *db = calloc(1, sizeof *db);
  if (!db) {
    free(rec);
    free(features);
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate a database");
  }
  db->p = *p;
  db->rec = rec;
  db->features = features;
  *out = db;
  return SATF_OK;
}

void satf_db_destroy(satf_db *db) {
  if (db) {
    free(db->rec);
    free(db->rec16);
    free(db->features);
    free(db->norm);
    satf_kdtree_destroy(db->tree);
    free(db);
  }
}

const satf_build_params *satf_db_params(const satf_db *db) { return &db->p; }
int satf_db_channels(const satf_db *db) {
  return satf_build_params_channels(&db->p);
}
satf_record_kind satf_db_kind(const satf_db *db) { return db->p.kind; }
const float *satf_db_absorption_levels(const satf_db *db, int *count) {
  int fiber = db->p.kind == SATF_RECORD_FIBER;
  *count = fiber ? db->p.fiber.levels : 0;
  return fiber ? db->p.fiber.sigma_a : NULL;
}
int satf_db_width(const satf_db *db) { return db->p.trace.width; }
int satf_db_samples(const satf_db *db) { return db->p.samples; }

float *satf_db_sample_features(satf_db *db, int i) {
  return db->features + (size_t)i * SATF_FEATURES;
}
size_t satf_db_record_offset(const satf_db *db, int sample, int iv, int il) {
  return (size_t)sample * values_per_sample(&db->p) +
         ((size_t)il * (size_t)db->p.n_view + (size_t)iv) *
             (size_t)satf_build_params_channels(&db->p) *
             (size_t)db->p.trace.width;
}

void satf_db_record_mut(satf_db *db, int sample, int iv, int il, float **re,
                        float **alpha) {
  *re = db->rec + satf_db_record_offset(db, sample, iv, il);
  *alpha = *re + db->p.trace.width;
}

float *satf_db_record_channels_mut(satf_db *db, int sample, int iv, int il) {
  satf_db_halfs_drop(db);
  return db->rec + satf_db_record_offset(db, sample, iv, il);
}

const float *satf_db_record_channels(const satf_db *db, int sample, int iv,
                                     int il) {
  return db->rec + satf_db_record_offset(db, sample, iv, il);
}

static float round_to_half(float x) {
  return imath_half_to_float(imath_float_to_half(x));
}

static void halfs_build(satf_db *db);

satf_status satf_db_index(satf_db *db, satf_error *err) {
  int n = db->p.samples;
  for (int a = 0; a < SATF_FEATURES; a++) {
    db->lo[a] = INFINITY;
    db->hi[a] = -INFINITY;
  }
  for (int i = 0; i < n; i++)
    for (int a = 0; a < SATF_FEATURES; a++) {
      float v = db->features[i * SATF_FEATURES + a];
      if (!isfinite(v))
        return satf_error_set(err, SATF_ERR_CORRUPT,
                              "feature %d of sample %d is not finite", a, i);
      db->lo[a] = v < db->lo[a] ? v : db->lo[a];
      db->hi[a] = v > db->hi[a] ? v : db->hi[a];
    }
  /* Features are compared after scaling each to [0, 1] over the database,
   * so density and the centroids weigh alike. */
  for (int a = 0; a < SATF_FEATURES; a++)
    db->scale[a] =
        db->hi[a] > db->lo[a] ? 1.0f / (db->hi[a] - db->lo[a]) : 1.0f;
  free(db->norm);
  satf_kdtree_destroy(db->tree);
  db->tree = NULL;
  db->norm = malloc((size_t)n * SATF_FEATURES * sizeof(float));
  if (!db->norm)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate the index");
  for (int i = 0; i < n; i++)
    for (int a = 0; a < SATF_FEATURES; a++)
      db->norm[i * SATF_FEATURES + a] =
          (db->features[i * SATF_FEATURES + a] - db->lo[a]) * db->scale[a];
  db->tree = satf_kdtree_build(db->norm, n);
  if (!db->tree)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot build the k-d tree");
  halfs_build(db);
  return SATF_OK;
}

/* A fibre record's reflectance channel is the total at the first level,
 * R + TT[0] + TRT[0] + MS[0] (satf/db.h), for callers that read
 * reflectance and alpha only. */
static void fiber_reflectance(satf_db *db) {
  const satf_build_params *p = &db->p;
  if (p->kind != SATF_RECORD_FIBER)
    return;
  int K = p->fiber.levels;
  size_t w = (size_t)p->trace.width;
  for (int i = 0; i < p->samples; i++)
    for (int il = 0; il < p->n_light; il++)
      for (int iv = 0; iv < p->n_view; iv++) {
        float *r = db->rec + satf_db_record_offset(db, i, iv, il);
        for (size_t j = 0; j < w; j++)
          r[j] = r[SATF_DB_CH_R * w + j] + r[SATF_DB_CH_TT(0) * w + j] +
                 r[SATF_DB_CH_TRT(0, K) * w + j] +
                 r[SATF_DB_CH_MS(0, K) * w + j];
      }
}

satf_status satf_db_finalize(satf_db *db, satf_error *err) {
  size_t n = values_per_sample(&db->p) * (size_t)db->p.samples;
  fiber_reflectance(db);
  for (size_t i = 0; i < n; i++)
    db->rec[i] = round_to_half(db->rec[i]);
  return satf_db_index(db, err);
}

void satf_db_record(const satf_db *db, int sample, int iv, int il,
                    const float **re, const float **alpha) {
  *re = db->rec + satf_db_record_offset(db, sample, iv, il);
  *alpha = *re + db->p.trace.width;
}

const float *satf_db_features(const satf_db *db, int sample) {
  return db->features + (size_t)sample * SATF_FEATURES;
}

void satf_db_feature_range(const satf_db *db, float lo[SATF_FEATURES],
                           float hi[SATF_FEATURES]) {
  memcpy(lo, db->lo, sizeof db->lo);
  memcpy(hi, db->hi, sizeof db->hi);
}

int satf_db_nearest(const satf_db *db, const float feature[SATF_FEATURES],
                    int k, int *index, float *dist2) {
  float q[SATF_FEATURES];
  for (int a = 0; a < SATF_FEATURES; a++)
    q[a] = (feature[a] - db->lo[a]) * db->scale[a];
  return satf_kdtree_nearest(db->tree, q, k, index, dist2);
}

/* Position of an azimuth on a periodic grid of n stored angles. Values
 * within 1e-4 of a grid angle snap to it, so a look-up at a stored angle
 * returns the stored record exactly despite float rounding of 2 pi k / n. */
static void angle_cell(float theta, int n, int *i0, int *i1, float *f) {
  double x = (double)theta / SATF_TWO_PI * n;
  /* into [0, n); the maps' azimuths are there already (maps_azimuth), and
   * with the division and floor corners_of took 11% of the CPU samples of
   * hair_7c's physical frames (perf); either branch then snaps alike */
  if (!(x >= 0.0 && x < (double)n))
    x -= floor(x / n) * n;
  double r = floor(x + 0.5);
  if (fabs(x - r) < 1e-4)
    x = r;
  int i = (int)floor(x);
  *f = (float)(x - i);
  /* i is in [0, n] (n after snapping up): a wrap, no division */
  *i0 = i >= n ? i - n : i;
  *i1 = *i0 + 1 == n ? 0 : *i0 + 1;
}

/* A clone of a function for processors with AVX2 (8 floats a vector
 * against SSE2's 4), chosen when the program loads; the same operations
 * in the same order (no fused multiply-adds: C11 does not contract), so
 * the same values. GCC on x86-64 only (clang's clones need a newer
 * compiler than the CI's). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) &&         \
    defined(__linux__)
#define AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define AVX2_CLONE
#endif

/* out = (accumulate ? out : 0) + sum_c c[c] src[c]; separate, restrict-
 * qualified streams so the compiler vectorises it. With c = (1, 0, 0, 0)
 * the result is src[0] exactly. */
AVX2_CLONE static void blend4(float *restrict out, const float *const src[4],
                              const float c[4], int w, int accumulate) {
  const float *restrict s0 = src[0], *restrict s1 = src[1];
  const float *restrict s2 = src[2], *restrict s3 = src[3];
  if (accumulate) {
    for (int j = 0; j < w; j++)
      out[j] += c[0] * s0[j] + c[1] * s1[j] + c[2] * s2[j] + c[3] * s3[j];
  } else {
    for (int j = 0; j < w; j++)
      out[j] = c[0] * s0[j] + c[1] * s1[j] + c[2] * s2[j] + c[3] * s3[j];
  }
}

/* The half-float records (satf_db.rec16): x86-64 processors with AVX2 and
 * F16C, GCC or clang; blend_half is blend4 reading halfs, each converted
 * to the float it equals, then the same operations in the same order (no
 * fused multiply-adds), so the same values. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#include <immintrin.h>
#define DB_HALFS 1

/* Neighbour n's four records (src[4n..4n+3], weights c[4n..4n+3]) blended
 * as blend4 does, then summed over n in order: out = v_0 + v_1 + ..., each
 * v_n = c s_0 + c s_1 + c s_2 + c s_3 left to right, the values of blend4
 * called per neighbour with accumulate, but out is written once (one pass
 * over the run instead of one per neighbour). */
__attribute__((target("avx2,f16c"))) static void
blend_half(float *restrict out, const uint16_t *const src[], const float c[],
           int count, int w) {
  int j = 0;
  for (; j + 8 <= w; j += 8) {
    __m256 acc = _mm256_setzero_ps();
    for (int n = 0; n < count; n++) {
      const uint16_t *const *s = src + 4 * n;
      const float *cn = c + 4 * n;
      __m256 s0 = _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(s[0] + j)));
      __m256 s1 = _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(s[1] + j)));
      __m256 s2 = _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(s[2] + j)));
      __m256 s3 = _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(s[3] + j)));
      __m256 v = _mm256_add_ps(
          _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(cn[0]), s0),
                                      _mm256_mul_ps(_mm256_set1_ps(cn[1]), s1)),
                        _mm256_mul_ps(_mm256_set1_ps(cn[2]), s2)),
          _mm256_mul_ps(_mm256_set1_ps(cn[3]), s3));
      acc = n > 0 ? _mm256_add_ps(acc, v) : v;
    }
    _mm256_storeu_ps(out + j, acc);
  }
  for (; j < w; j++) {
    float acc = 0.0f;
    for (int n = 0; n < count; n++) {
      const uint16_t *const *s = src + 4 * n;
      const float *cn = c + 4 * n;
      float v = cn[0] * _cvtsh_ss(s[0][j]) + cn[1] * _cvtsh_ss(s[1][j]) +
                cn[2] * _cvtsh_ss(s[2][j]) + cn[3] * _cvtsh_ss(s[3][j]);
      acc = n > 0 ? acc + v : v;
    }
    out[j] = acc;
  }
}
#endif

void satf_db_halfs_drop(satf_db *db) {
  free(db->rec16);
  db->rec16 = NULL;
}

/* db->rec16 where the processor reads halfs fast and every value is a half
 * exactly (what the file keeps and satf_db_finalize rounds to); without
 * it (or its memory) look-ups read rec. */
static void halfs_build(satf_db *db) {
  satf_db_halfs_drop(db);
#ifdef DB_HALFS
  if (!satf_cpu_has_f16c(1))
    return;
  size_t n = values_per_sample(&db->p) * (size_t)db->p.samples;
  uint16_t *h = malloc(n * sizeof *h);
  for (size_t i = 0; h && i < n; i++) {
    h[i] = imath_float_to_half(db->rec[i]);
    if (imath_half_to_float(h[i]) != db->rec[i]) {
      free(h);
      return;
    }
  }
  db->rec16 = h;
#endif
}

void satf_db_neighbors_find(const satf_db *db,
                            const float feature[SATF_FEATURES], int k,
                            satf_db_neighbors *out) {
  float d2[SATF_DB_KMAX];
  if (k < 1)
    k = 1;
  if (k > SATF_DB_KMAX)
    k = SATF_DB_KMAX;
  int found = satf_db_nearest(db, feature, k, out->index, d2);
  /* Inverse-distance weights; an exact hit takes all the weight. */
  if (found > 1 && d2[0] <= 0.0f)
    found = 1;
  float total = 0.0f;
  for (int n = 0; n < found; n++) {
    out->weight[n] = found == 1 ? 1.0f : 1.0f / sqrtf(d2[n]);
    total += out->weight[n];
  }
  for (int n = 0; n < found; n++)
    out->weight[n] /= total;
  out->count = found;
}

/* The four stored azimuth pairs around (theta_v, theta_l), periodically,
 * and their bilinear weights. */
typedef satf_db_cell corners;

static void corners_of(const satf_db *db, float theta_v, float theta_l,
                       corners *c) {
  float fv, fl;
  angle_cell(theta_v, db->p.n_view, &c->v[0], &c->v[1], &fv);
  angle_cell(theta_l, db->p.n_light, &c->l[0], &c->l[1], &fl);
  c->bw[0] = (1 - fv) * (1 - fl);
  c->bw[1] = fv * (1 - fl);
  c->bw[2] = (1 - fv) * fl;
  c->bw[3] = fv * fl;
}

void satf_db_cell_find(const satf_db *db, float theta_v, float theta_l,
                       satf_db_cell *out) {
  corners_of(db, theta_v, theta_l, out);
}

/* Offsets in rec of the four corners' records of sample 0, channel ch0,
 * and the values of one sample: record (sample, corner k) starts at
 * base[k] + sample * stride (satf_db_record_offset, found once per look-up
 * rather than per record). */
static size_t corner_offsets(const satf_db *db, const corners *cs, int ch0,
                             size_t base[4]) {
  size_t skip = (size_t)ch0 * (size_t)db->p.trace.width;
  for (int k = 0; k < 4; k++)
    base[k] = satf_db_record_offset(db, 0, cs->v[k & 1], cs->l[k >> 1]) + skip;
  return values_per_sample(&db->p);
}

/* Channels [ch0, ch0 + nch) of the corners' records of every neighbour:
 * one contiguous run of nch * width values each (records are
 * channel-major), blended into out (blend4 per neighbour; with halfs, all
 * neighbours in one pass, blend_half). Per value the sums run in the order
 * of a channel-by-channel blend, so any range gives the values of the full
 * look-up, bit for bit. */
static void blend_range(const satf_db *db, const satf_db_neighbors *nb,
                        const corners *cs, int ch0, int nch, float *out) {
  int run = nch * db->p.trace.width;
  size_t base[4], stride = corner_offsets(db, cs, ch0, base);
#ifdef DB_HALFS
  if (db->rec16) {
    const uint16_t *r[4 * SATF_DB_KMAX];
    float c[4 * SATF_DB_KMAX];
    for (int n = 0; n < nb->count; n++)
      for (int k = 0; k < 4; k++) {
        r[4 * n + k] = db->rec16 + base[k] + (size_t)nb->index[n] * stride;
        c[4 * n + k] = nb->weight[n] * cs->bw[k];
      }
    blend_half(out, r, c, nb->count, run);
    return;
  }
#endif
  for (int n = 0; n < nb->count; n++) {
    const float *r[4];
    float c[4];
    for (int k = 0; k < 4; k++) {
      r[k] = db->rec + base[k] + (size_t)nb->index[n] * stride;
      c[k] = nb->weight[n] * cs->bw[k];
    }
    blend4(out, r, c, run, n > 0);
  }
}

void satf_db_lookup_neighbors_range(const satf_db *db,
                                    const satf_db_neighbors *nb, float theta_v,
                                    float theta_l, int ch0, int nch,
                                    float *out) {
  corners cs;
  corners_of(db, theta_v, theta_l, &cs);
  blend_range(db, nb, &cs, ch0, nch, out);
}

void satf_db_lookup_cell_range(const satf_db *db, const satf_db_neighbors *nb,
                               const satf_db_cell *cell, int ch0, int nch,
                               float *out) {
  blend_range(db, nb, cell, ch0, nch, out);
}

void satf_db_prefetch(const satf_db *db, const satf_db_neighbors *nb,
                      float theta_v, float theta_l, int ch0, int nch) {
  corners cs;
  corners_of(db, theta_v, theta_l, &cs);
  satf_db_prefetch_cell(db, nb, &cs, ch0, nch);
}

void satf_db_prefetch_cell(const satf_db *db, const satf_db_neighbors *nb,
                           const satf_db_cell *cell, int ch0, int nch) {
#if defined(__GNUC__) || defined(__clang__)
  const corners cs = *cell;
  size_t w = (size_t)db->p.trace.width;
  /* the records the look-up reads: halfs when there are */
  size_t size = db->rec16 ? sizeof *db->rec16 : sizeof *db->rec;
  const char *base =
      db->rec16 ? (const char *)db->rec16 : (const char *)db->rec;
  size_t bytes = (size_t)nch * w * size;
  size_t at[4], stride = corner_offsets(db, &cs, ch0, at);
  for (int n = 0; n < nb->count; n++)
    for (int k = 0; k < 4; k++) {
      const char *r = base + (at[k] + (size_t)nb->index[n] * stride) * size;
      for (size_t b = 0; b < bytes; b += 64)
        __builtin_prefetch(r + b);
      __builtin_prefetch(r + bytes - 1); /* a run need not start a line */
    }
#else
  (void)db, (void)nb, (void)cell, (void)ch0, (void)nch;
#endif
}

void satf_db_lookup_neighbors(const satf_db *db, const satf_db_neighbors *nb,
                              float theta_v, float theta_l, float *re,
                              float *alpha) {
  float both[2 * SATF_DB_LOOKUP_MAX_WIDTH];
  int w = db->p.trace.width;
  if (w > SATF_DB_LOOKUP_MAX_WIDTH) { /* rare: blend one channel at a time */
    satf_db_lookup_neighbors_range(db, nb, theta_v, theta_l,
                                   SATF_DB_CH_REFLECTANCE, 1, re);
    satf_db_lookup_neighbors_range(db, nb, theta_v, theta_l, SATF_DB_CH_ALPHA,
                                   1, alpha);
    return;
  }
  satf_db_lookup_neighbors_range(db, nb, theta_v, theta_l, 0, 2, both);
  memcpy(re, both, (size_t)w * sizeof(float));
  memcpy(alpha, both + w, (size_t)w * sizeof(float));
}

void satf_db_lookup_neighbors_channels(const satf_db *db,
                                       const satf_db_neighbors *nb,
                                       float theta_v, float theta_l,
                                       float *out) {
  satf_db_lookup_neighbors_range(db, nb, theta_v, theta_l, 0,
                                 satf_db_channels(db), out);
}

void satf_db_lookup(const satf_db *db, const float feature[SATF_FEATURES],
                    float theta_v, float theta_l, int k, float *re,
                    float *alpha) {
  satf_db_neighbors nb;
  satf_db_neighbors_find(db, feature, k, &nb);
  satf_db_lookup_neighbors(db, &nb, theta_v, theta_l, re, alpha);
}

static uint64_t fnv_words(uint64_t h, const void *data, size_t bytes) {
  const unsigned char *p = data;
  /* FNV-1a over 32-bit little-endian words: 4x fewer multiplies than the
   * byte-wise form and still sensitive to every bit. */
  for (size_t i = 0; i + 4 <= bytes; i += 4) {
    uint32_t w = (uint32_t)p[i] | (uint32_t)p[i + 1] << 8 |
                 (uint32_t)p[i + 2] << 16 | (uint32_t)p[i + 3] << 24;
    h = (h ^ w) * 0x100000001B3ull;
  }
  return h;
}

uint64_t satf_db_fnv(uint64_t h, const void *data, size_t bytes) {
  return fnv_words(h, data, bytes);
}

/* Version 2 (fibre records) adds the fibre tracer's parameters. */
static uint64_t fiber_params_hash(uint64_t h,
                                  const satf_fiber_trace_params *f) {
  int32_t ints[3] = {f->levels, f->sub_rays, f->max_bounces};
  float floats[2 + SATF_DB_LEVELS_MAX] = {f->eta, f->beta_n};
  for (int k = 0; k < f->levels && k < SATF_DB_LEVELS_MAX; k++)
    floats[2 + k] = f->sigma_a[k];
  h = fnv_words(h, ints, sizeof ints);
  return fnv_words(h, floats, sizeof floats);
}

uint64_t satf_db_params_hash(const satf_build_params *p) {
  uint64_t h = 0xCBF29CE484222325ull;
  int32_t ints[7] = {p->samples,
                     p->n_view,
                     p->n_light,
                     p->grid,
                     p->trace.width,
                     p->trace.self_shadow,
                     satf_build_params_version(p)};
  float floats[11] = {p->shape.r_inner,
                      p->shape.r_outer,
                      p->shape.phase_span,
                      p->trace.extinction,
                      p->trace.ambient,
                      p->trace.diffuse,
                      p->trace.specular,
                      p->trace.shininess,
                      p->trace.epsilon,
                      p->trace.smooth_ratio,
                      0.0f};
  uint32_t seed[2] = {(uint32_t)p->seed, (uint32_t)(p->seed >> 32)};
  h = fnv_words(h, ints, sizeof ints);
  h = fnv_words(h, floats, sizeof floats);
  h = fnv_words(h, seed, sizeof seed);
  return p->kind == SATF_RECORD_FIBER ? fiber_params_hash(h, &p->fiber) : h;
}

uint64_t satf_db_payload_hash(const satf_db *db) {
  const satf_build_params *p = &db->p;
  uint64_t h = satf_db_params_hash(p);
  size_t n = values_per_sample(p) * (size_t)p->samples;
  h = fnv_words(h, db->features,
                (size_t)p->samples * SATF_FEATURES * sizeof(float));
  h = fnv_words(h, db->rec, n * sizeof(float));
  return h;
}
