/* import_cluster.c - grouping strands into clusters: k-means (k-means++
 * seeding, Lloyd iterations) on strands resampled to a fixed number of
 * points evenly spaced in arc length, so a strand's feature vector is its
 * shape and place at once (SATF sec. 3.1 groups hair into clusters before
 * fitting generalized cylinders). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/common.h"

satf_import_cluster_params satf_import_cluster_params_default(void) {
  satf_import_cluster_params p = {0, 12, 20, 1, 0};
  return p;
}

void satf_import_resample(const satf_strand_set *s, int i, int samples,
                          float *out) {
  int n;
  const float *p = satf_strand_set_strand(s, i, &n);
  double total = satf_strand_set_length(s, i);
  if (!(total > 0.0)) { /* every point equal: repeat the root */
    for (int k = 0; k < samples; k++)
      memcpy(out + 3 * k, p, 3 * sizeof(float));
    return;
  }
  int seg = 0;
  double seg_start = 0.0;
  for (int k = 0; k < samples; k++) {
    double target = total * (double)k / (double)(samples - 1);
    for (;;) {
      const float *a = p + 3 * seg, *b = a + 3;
      double len = sqrt((double)(b[0] - a[0]) * (b[0] - a[0]) +
                        (double)(b[1] - a[1]) * (b[1] - a[1]) +
                        (double)(b[2] - a[2]) * (b[2] - a[2]));
      if (seg_start + len >= target || seg == n - 2) {
        double f = len > 0.0 ? (target - seg_start) / len : 0.0;
        f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
        for (int c = 0; c < 3; c++)
          out[3 * k + c] = (float)(a[c] + f * (b[c] - a[c]));
        break;
      }
      seg_start += len;
      seg++;
    }
  }
}

static double dist2(const float *a, const float *b, int d) {
  float s = 0.0f;
  for (int k = 0; k < d; k++) {
    float e = a[k] - b[k];
    s += e * e;
  }
  return s;
}

enum { ASSIGN_BLOCK = 256 };

typedef struct kmeans_ctx {
  const float *feat;
  const float *centres;
  int n, d, k;
  int *labels;
  float *best;
} kmeans_ctx;

static int assign_range(void *vctx, size_t blk, int thread) {
  (void)thread;
  const kmeans_ctx *c = vctx;
  size_t lo = blk * ASSIGN_BLOCK, hi = lo + ASSIGN_BLOCK;
  if (hi > (size_t)c->n)
    hi = (size_t)c->n;
  for (size_t i = lo; i < hi; i++) {
    const float *f = c->feat + i * (size_t)c->d;
    double best = DBL_MAX;
    int arg = 0;
    for (int q = 0; q < c->k; q++) {
      double e = dist2(f, c->centres + (size_t)q * c->d, c->d);
      if (e < best) {
        best = e;
        arg = q;
      }
    }
    c->labels[i] = arg;
    c->best[i] = (float)best;
  }
  return 0;
}

/* k-means++ seeding: each new centre is drawn with probability
 * proportional to the squared distance to the nearest centre so far. */
static void seed_centres(const float *feat, int n, int d, int k, uint64_t seed,
                         float *centres, float *near) {
  satf_rng rng;
  satf_rng_seed(&rng, seed, 0xC1A55);
  int first = (int)satf_rng_below(&rng, (uint32_t)n);
  memcpy(centres, feat + (size_t)first * d, (size_t)d * sizeof(float));
  for (int i = 0; i < n; i++)
    near[i] = (float)dist2(feat + (size_t)i * d, centres, d);
  for (int q = 1; q < k; q++) {
    double total = 0.0;
    for (int i = 0; i < n; i++)
      total += near[i];
    int pick = 0;
    if (total > 0.0) {
      double r = satf_rng_uniform(&rng) * total, acc = 0.0;
      for (pick = 0; pick < n - 1; pick++) {
        acc += near[pick];
        if (acc >= r)
          break;
      }
    } else {
      pick = (int)satf_rng_below(&rng, (uint32_t)n);
    }
    float *c = centres + (size_t)q * d;
    memcpy(c, feat + (size_t)pick * d, (size_t)d * sizeof(float));
    for (int i = 0; i < n; i++) {
      float e = (float)dist2(feat + (size_t)i * d, c, d);
      if (e < near[i])
        near[i] = e;
    }
  }
}

/* Lloyd's algorithm on n feature vectors of d floats. Returns 0 or -1 when
 * memory runs out. */
static int kmeans_core(const float *feat, int n, int d, int k, uint64_t seed,
                       int iterations, int threads, int *labels, double *rms,
                       satf_import_progress_fn progress, void *pctx) {
  float *centres = malloc((size_t)k * d * sizeof(float));
  float *best = malloc((size_t)n * sizeof(float));
  double *sum = malloc((size_t)k * d * sizeof(double));
  int *count = malloc((size_t)k * sizeof(int));
  if (!centres || !best || !sum || !count) {
    free(centres);
    free(best);
    free(sum);
    free(count);
    return -1;
  }
  seed_centres(feat, n, d, k, seed, centres, best);
  for (int i = 0; i < n; i++)
    labels[i] = -1;
  kmeans_ctx ctx = {feat, centres, n, d, k, NULL, best};
  int *next = malloc((size_t)n * sizeof(int));
  if (!next) {
    free(centres);
    free(best);
    free(sum);
    free(count);
    return -1;
  }
  ctx.labels = next;
  size_t blocks = ((size_t)n + ASSIGN_BLOCK - 1) / ASSIGN_BLOCK;
  for (int it = 0; it < iterations; it++) {
    satf_parallel_for(blocks, threads, assign_range, &ctx, NULL, NULL);
    int changed = 0;
    for (int i = 0; i < n; i++) {
      changed += next[i] != labels[i];
      labels[i] = next[i];
    }
    if (progress)
      progress(pctx, (size_t)it + 1, (size_t)iterations);
    if (!changed)
      break;
    memset(sum, 0, (size_t)k * d * sizeof(double));
    memset(count, 0, (size_t)k * sizeof(int));
    for (int i = 0; i < n; i++) {
      const float *f = feat + (size_t)i * d;
      double *s = sum + (size_t)labels[i] * d;
      for (int c = 0; c < d; c++)
        s[c] += f[c];
      count[labels[i]]++;
    }
    for (int q = 0; q < k; q++) {
      float *c = centres + (size_t)q * d;
      if (count[q] > 0) {
        for (int e = 0; e < d; e++)
          c[e] = (float)(sum[(size_t)q * d + e] / count[q]);
        continue;
      }
      /* An empty cluster takes the strand farthest from its centre. */
      int far = 0;
      for (int i = 1; i < n; i++)
        if (best[i] > best[far])
          far = i;
      memcpy(c, feat + (size_t)far * d, (size_t)d * sizeof(float));
      best[far] = 0.0f;
    }
  }
  double total = 0.0;
  for (int i = 0; i < n; i++)
    total += best[i];
  if (rms)
    *rms = sqrt(total / ((double)n * (d / 3)));
  free(next);
  free(centres);
  free(best);
  free(sum);
  free(count);
  return 0;
}

static satf_status check_params(const satf_import_cluster_params *p,
                                satf_error *err) {
  if (p->clusters < 0 || p->clusters > SATF_IMPORT_MAX_CLUSTERS ||
      p->samples < 2 || p->samples > 256 || p->iterations < 1)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "clustering: %d clusters (0..%d), %d samples "
                          "(2..256), %d iterations (>= 1)",
                          p->clusters, SATF_IMPORT_MAX_CLUSTERS, p->samples,
                          p->iterations);
  return SATF_OK;
}

/* Features of the strands `pick` (or all strands when pick is NULL). */
static float *features(const satf_strand_set *s, const int *pick, int n,
                       int samples) {
  size_t d = 3 * (size_t)samples;
  float *f = malloc((size_t)n * d * sizeof(float));
  if (f)
    for (int i = 0; i < n; i++)
      satf_import_resample(s, pick ? pick[i] : i, samples, f + (size_t)i * d);
  return f;
}

satf_status satf_import_choose_clusters(const satf_strand_set *s,
                                        const satf_import_cluster_params *p,
                                        int *clusters, satf_error *err) {
  satf_status st = check_params(p, err);
  if (st != SATF_OK)
    return st;
  int n = satf_strand_set_count(s);
  int m = n < 4000 ? n : 4000;
  int *pick = malloc((size_t)m * sizeof(int));
  int *labels = malloc((size_t)m * sizeof(int));
  float *f = NULL;
  if (pick) {
    for (int i = 0; i < m; i++)
      pick[i] = (int)((int64_t)i * n / m);
    f = features(s, pick, m, p->samples);
  }
  if (!pick || !labels || !f) {
    free(pick);
    free(labels);
    free(f);
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  }
  float lo[3], hi[3];
  satf_strand_set_bounds(s, lo, hi);
  double diag = sqrt((double)(hi[0] - lo[0]) * (hi[0] - lo[0]) +
                     (double)(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (double)(hi[2] - lo[2]) * (hi[2] - lo[2]));
  int limit = n / 4 < 1024 ? n / 4 : 1024;
  int k = 1;
  for (;;) {
    double rms = 0.0;
    if (kmeans_core(f, m, 3 * p->samples, k, p->seed, p->iterations, p->threads,
                    labels, &rms, NULL, NULL) != 0) {
      st = satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
      break;
    }
    if (rms <= 0.03 * diag || 2 * k > limit)
      break;
    k *= 2;
  }
  free(pick);
  free(labels);
  free(f);
  *clusters = k;
  return st;
}

satf_status satf_import_kmeans(const satf_strand_set *s,
                               const satf_import_cluster_params *p, int *labels,
                               int *n_clusters, float *rms,
                               satf_import_progress_fn progress,
                               void *progress_ctx, satf_error *err) {
  satf_status st = check_params(p, err);
  if (st != SATF_OK)
    return st;
  int n = satf_strand_set_count(s), k = p->clusters;
  if (k == 0) {
    st = satf_import_choose_clusters(s, p, &k, err);
    if (st != SATF_OK)
      return st;
  }
  if (k > n)
    k = n;
  float *f = features(s, NULL, n, p->samples);
  if (!f)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "clustering: cannot resample %d strands", n);
  double r = 0.0;
  int bad = kmeans_core(f, n, 3 * p->samples, k, p->seed, p->iterations,
                        p->threads, labels, &r, progress, progress_ctx);
  free(f);
  if (bad)
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  /* Renumber so clusters appear in order of their first strand and no
   * index is unused. */
  int *map = malloc((size_t)k * sizeof(int));
  if (!map)
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  for (int q = 0; q < k; q++)
    map[q] = -1;
  int used = 0;
  for (int i = 0; i < n; i++) {
    if (map[labels[i]] < 0)
      map[labels[i]] = used++;
    labels[i] = map[labels[i]];
  }
  free(map);
  *n_clusters = used;
  if (rms)
    *rms = (float)r;
  return SATF_OK;
}

satf_status satf_import_members(const int *labels, int n_strands, int c,
                                int **members, int *n_members,
                                satf_error *err) {
  int m = 0;
  for (int i = 0; i < n_strands; i++)
    m += labels[i] == c;
  *members = malloc((size_t)(m ? m : 1) * sizeof(int));
  if (!*members)
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  m = 0;
  for (int i = 0; i < n_strands; i++)
    if (labels[i] == c)
      (*members)[m++] = i;
  *n_members = m;
  return SATF_OK;
}
