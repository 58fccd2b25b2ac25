/* relevel.c - a fibre database's records at other absorption levels.
 *
 * db.h's record contract stores the absorbing lobes (TT, TRT, MS) at a few
 * absorption levels and asks readers to interpolate log-linearly in sigma_a
 * between them. A renderer shading one hair colour needs the same three
 * values (its RGB sigma_a) for every record, so it re-levels the whole
 * database once instead of interpolating after every look-up: a frame then
 * blends 3 + 3 x 3 channels and takes no logarithm. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/db.h"

/* Between levels k and k + 1 the lobes fall about exponentially with the
 * absorption (one internal pass transmits exp(-2 sigma_a cos gamma_t)), so
 * the logarithms are interpolated: exact for a single path length. Past
 * the last level the last step's rate continues (never rising); before
 * the first, the first level's value holds. A zero on either side falls
 * back to linear interpolation. */
float satf_db_level_value(const float *levels, const float *values, int count,
                          float sigma) {
  if (count <= 1 || sigma <= levels[0])
    return values[0];
  int k = 0;
  while (k < count - 2 && sigma > levels[k + 1])
    k++;
  float v0 = values[k], v1 = values[k + 1];
  float w = (sigma - levels[k]) / (levels[k + 1] - levels[k]);
  if (w > 1.0f && v1 >= v0) /* past the last level: no rise */
    return v1;
  if (v0 > 0.0f && v1 > 0.0f)
    return expf(logf(v0) + w * (logf(v1) - logf(v0)));
  float v = v0 + w * (v1 - v0);
  return v > 0.0f ? v : 0.0f;
}

typedef struct relevel_job {
  const satf_db *src;
  satf_db *dst;
  const float *sigma; /* the new levels */
  int n;
} relevel_job;

static int relevel_sample(void *ctx, size_t i, int thread) {
  (void)thread;
  const relevel_job *j = ctx;
  const satf_build_params *p = satf_db_params(j->src);
  int w = p->trace.width, K;
  const float *levels = satf_db_absorption_levels(j->src, &K);
  memcpy(satf_db_sample_features(j->dst, (int)i),
         satf_db_features(j->src, (int)i), SATF_FEATURES * sizeof(float));
  float values[SATF_DB_LEVELS_MAX];
  for (int iv = 0; iv < p->n_view; iv++)
    for (int il = 0; il < p->n_light; il++) {
      const float *a = satf_db_record_channels(j->src, (int)i, iv, il);
      float *b = satf_db_record_channels_mut(j->dst, (int)i, iv, il);
      /* reflectance, alpha and R do not depend on the absorption */
      memcpy(b, a, 3 * (size_t)w * sizeof(float));
      for (int lobe = 0; lobe < 3; lobe++)
        for (int x = 0; x < w; x++) {
          for (int k = 0; k < K; k++)
            values[k] = a[(3 + lobe * K + k) * w + x];
          for (int c = 0; c < j->n; c++)
            b[(3 + lobe * j->n + c) * w + x] =
                satf_db_level_value(levels, values, K, j->sigma[c]);
        }
    }
  return 0;
}

satf_status satf_db_relevel(const satf_db *db, const float *sigma, int n,
                            int threads, satf_db **out, satf_error *err) {
  *out = NULL;
  if (satf_db_kind(db) != SATF_RECORD_FIBER)
    return satf_error_set(err, SATF_ERR_INCOMPATIBLE,
                          "only a fibre database has absorption levels");
  satf_build_params p = *satf_db_params(db);
  if (n < 1 || n > SATF_DB_LEVELS_MAX)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%d absorption levels: 1 to %d", n,
                          SATF_DB_LEVELS_MAX);
  p.fiber.levels = n;
  memcpy(p.fiber.sigma_a, sigma, (size_t)n * sizeof(float));
  satf_db *dst;
  satf_status st = satf_db_create(&p, &dst, err);
  if (st != SATF_OK)
    return st;
  relevel_job job = {db, dst, sigma, n};
  if (threads <= 0)
    threads = satf_cpu_count();
  satf_parallel_for((size_t)p.samples, threads, relevel_sample, &job, NULL,
                    NULL);
  st = satf_db_finalize(dst, err);
  if (st != SATF_OK) {
    satf_db_destroy(dst);
    return st;
  }
  *out = dst;
  return SATF_OK;
}
