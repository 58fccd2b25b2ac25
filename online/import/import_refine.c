/* import_refine.c - adaptive clustering: k-means on the strands' shapes for
 * a start, then every cluster is fitted (SATF eq. 1-2, import_fit.c) and
 * held to a tolerance measured on its own strands (satf_import_fit_measures:
 * distance of the points to the trajectory and to the envelope surface,
 * envelope area per strand, length over diameter); a cluster that fails
 * gets more trajectory control points or is split in two, until every
 * cluster passes. So a straight bundle stays one cluster, curls get as many
 * as they need, and fur (short strands over a surface) becomes patches no
 * wider than the strands are long instead of rings. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "import_internal.h"
#include "satf/common.h"

#define SPLIT_SAMPLES 12
#define SPLIT_ITERATIONS 12
#define SPLIT_MAX 8

satf_import_refine_params
satf_import_refine_params_for(const satf_strand_set *s, satf_import_quality q,
                              double tolerance) {
  satf_import_refine_params p;
  memset(&p, 0, sizeof p);
  float lo[3], hi[3];
  satf_strand_set_bounds(s, lo, hi);
  double diag = sqrt((double)(hi[0] - lo[0]) * (hi[0] - lo[0]) +
                     (double)(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (double)(hi[2] - lo[2]) * (hi[2] - lo[2]));
  static const double frac[3] = {0.04, 0.02, 0.01};
  static const float area[3] = {32.0f, 16.0f, 8.0f};
  int k = q == SATF_IMPORT_QUALITY_DRAFT  ? 0
          : q == SATF_IMPORT_QUALITY_HIGH ? 2
                                          : 1;
  p.tolerance = (float)(tolerance > 0.0   ? tolerance
                        : tolerance < 0.0 ? -tolerance * diag
                                          : frac[k] * diag);
  if (!(p.tolerance > 0.0f))
    p.tolerance = 1e-6f;
  p.spacing = satf_strand_set_root_spacing(s);
  p.area_ratio = area[k];
  p.min_aspect = 1.0f;
  int n = satf_strand_set_count(s);
  p.initial = n / 256 < 1 ? 1 : n / 256 > 64 ? 64 : n / 256;
  p.max_clusters = SATF_IMPORT_MAX_CLUSTERS;
  p.max_ctrl = 32;
  p.threads = 0;
  return p;
}

float satf_import_fit_score(const satf_import_fit *fit,
                            const satf_import_refine_params *rp) {
  const satf_import_fit_measures *m = &fit->measures;
  float tol = rp->tolerance > 0.0f ? rp->tolerance : FLT_MIN;
  float s = m->trajectory[1] / tol;
  s = fmaxf(s, m->surface[1] / tol);
  if (rp->area_ratio > 0.0f && rp->spacing > 0.0f)
    s = fmaxf(s, m->area_per_strand /
                     (rp->area_ratio * rp->spacing * rp->spacing));
  if (rp->min_aspect > 0.0f)
    s = fmaxf(s, m->aspect > 0.0f ? rp->min_aspect / m->aspect : FLT_MAX);
  return s;
}

/* ---- Members of every cluster ------------------------------------------ */

int satf_import_groups_build(const int *labels, int n, int k,
                             satf_import_groups *g) {
  g->off = calloc((size_t)k + 1, sizeof(int));
  g->idx = malloc((size_t)(n ? n : 1) * sizeof(int));
  if (!g->off || !g->idx)
    return -1;
  for (int i = 0; i < n; i++)
    g->off[labels[i] + 1]++;
  for (int c = 0; c < k; c++)
    g->off[c + 1] += g->off[c];
  int *at = malloc((size_t)(k ? k : 1) * sizeof(int));
  if (!at)
    return -1;
  memcpy(at, g->off, (size_t)k * sizeof(int));
  for (int i = 0; i < n; i++)
    g->idx[at[labels[i]]++] = i;
  free(at);
  return 0;
}

void satf_import_groups_free(satf_import_groups *g) {
  free(g->off);
  free(g->idx);
  g->off = g->idx = NULL;
}

/* ---- Splitting one cluster ---------------------------------------------- */

static double dist2(const float *a, const float *b, int d) {
  double s = 0.0;
  for (int k = 0; k < d; k++) {
    double e = (double)a[k] - b[k];
    s += e * e;
  }
  return s;
}

/* k-means (k <= SPLIT_MAX) on the members' resampled shapes, seeded by
 * farthest points: the member farthest from their mean, then each next the
 * member farthest from the seeds so far (deterministic). side[i] receives
 * the part of member i; returns the parts used (1: the strands cannot be
 * told apart) or -1 when memory runs out. */
static int split_k(const satf_strand_set *s, const int *members, int n, int k,
                   int *side) {
  enum { D = 3 * SPLIT_SAMPLES };
  k = k < n ? k : n;
  float *f = malloc((size_t)n * D * sizeof(float));
  float *near = malloc((size_t)n * sizeof(float));
  if (!f || !near) {
    free(f);
    free(near);
    return -1;
  }
  double mean[D] = {0};
  for (int i = 0; i < n; i++) {
    satf_import_resample(s, members[i], SPLIT_SAMPLES, f + (size_t)i * D);
    for (int e = 0; e < D; e++)
      mean[e] += f[(size_t)i * D + e];
  }
  float c[SPLIT_MAX][D], m0[D];
  for (int e = 0; e < D; e++)
    m0[e] = (float)(mean[e] / n);
  for (int i = 0; i < n; i++)
    near[i] = (float)dist2(f + (size_t)i * D, m0, D);
  int used = 0;
  for (int q = 0; q < k; q++) {
    int far = -1;
    float fd = 0.0f;
    for (int i = 0; i < n; i++)
      if (near[i] > fd) {
        fd = near[i];
        far = i;
      }
    if (far < 0)
      break;
    memcpy(c[q], f + (size_t)far * D, sizeof c[q]);
    used++;
    if (q == 0) /* from now on: distance to the nearest seed */
      for (int i = 0; i < n; i++)
        near[i] = FLT_MAX;
    for (int i = 0; i < n; i++) {
      float d = (float)dist2(f + (size_t)i * D, c[q], D);
      near[i] = d < near[i] ? d : near[i];
    }
  }
  free(near);
  if (used < 2) {
    free(f);
    return 1;
  }
  k = used;
  for (int it = 0; it < SPLIT_ITERATIONS; it++) {
    double sum[SPLIT_MAX][D];
    int cnt[SPLIT_MAX], changed = 0;
    memset(sum, 0, sizeof sum);
    memset(cnt, 0, sizeof cnt);
    for (int i = 0; i < n; i++) {
      const float *x = f + (size_t)i * D;
      int best = 0;
      double bd = DBL_MAX;
      for (int q = 0; q < k; q++) {
        double d = dist2(x, c[q], D);
        if (d < bd) {
          bd = d;
          best = q;
        }
      }
      changed += it == 0 || side[i] != best;
      side[i] = best;
      cnt[best]++;
      for (int e = 0; e < D; e++)
        sum[best][e] += x[e];
    }
    if (!changed)
      break;
    for (int q = 0; q < k; q++)
      for (int e = 0; e < D && cnt[q] > 0; e++)
        c[q][e] = (float)(sum[q][e] / cnt[q]);
  }
  free(f);
  /* number the non-empty parts 0.. */
  int map[SPLIT_MAX], parts = 0;
  for (int q = 0; q < k; q++)
    map[q] = -1;
  for (int i = 0; i < n; i++) {
    if (map[side[i]] < 0)
      map[side[i]] = parts++;
    side[i] = map[side[i]];
  }
  return parts;
}

/* ---- The refinement ----------------------------------------------------- */

typedef struct refine {
  const satf_strand_set *s;
  const satf_import_refine_params *rp;
  const satf_import_fit_params *fp;
  int n_strands;
  float half_thickness; /* half the strands' mean thickness, 0: none */
  int k, cap;           /* clusters, room in the arrays */
  int *labels;
  satf_import_fit *fits;
  int *ctrl;               /* each cluster's trajectory control points */
  int *state;              /* STALE, FITTED, FINAL */
  float *score;            /* satf_import_fit_score of a fitted cluster */
  int *ctrl_tried;         /* more control points did not help */
  unsigned char *too_wide; /* strands_too_wide of a fitted cluster */
  satf_import_groups g;
  satf_error *errs;
  /* per round */
  int *batch;
  int n_batch;
  int *sides;      /* n_strands: the side of each member in a split */
  int *split_ones; /* parts each split made */
  int *split_want; /* parts each split is asked for */
} refine;

enum { STALE = 0, FITTED, FINAL };

/* A cluster of 2 .. SATF_SCENE_SPARSE_STRANDS strands is split into single
 * strands: the renderer draws such a cluster as its strands, rebuilt from
 * their tracks (import_tracks.c), and a track is exact only about a
 * trajectory fitted to its own strand. About a shared one, strands far
 * from it project to nearest-t points that double back and a twist
 * fitted to two or three strands swings by radians, so the rebuilt
 * strands zigzag (measured on Bangs_100: 39 of its 100 strands). */
static int sparse_group(const refine *r, int c) {
  int n = r->g.off[c + 1] - r->g.off[c];
  return n >= 2 && (n <= SATF_SCENE_SPARSE_STRANDS || r->too_wide[c]);
}

/* Whether cluster c's strands are too wide for its shells
 * (SATF_IMPORT_SHELL_STRAND_WIDTH): their mean thickness over the fitted
 * radius sqrt(mean A x mean B). Tufts of short strands (their mean length
 * at most half the trajectory's: fur) are left whole, since the renderer
 * draws them as their strands from each root to its tip. */
static int strands_too_wide(const refine *r, int c) {
  const satf_import_fit *f = &r->fits[c];
  const int *m = r->g.idx + r->g.off[c];
  int n = r->g.off[c + 1] - r->g.off[c];
  if (n < 2 || !satf_strand_set_thickness(r->s, 0) || f->n_radius < 1)
    return 0;
  double a = 0.0, b = 0.0, th = 0.0, len = 0.0;
  size_t points = 0;
  for (int j = 0; j < f->n_radius; j++) {
    a += f->a[j];
    b += f->b[j];
  }
  double radius = sqrt(a / f->n_radius * (b / f->n_radius));
  for (int i = 0; i < n; i++) {
    const float *t = satf_strand_set_thickness(r->s, m[i]);
    int k = satf_strand_set_points(r->s, m[i]);
    for (int j = 0; j < k; j++)
      th += t[j];
    points += (size_t)k;
    len += satf_strand_set_length(r->s, m[i]);
  }
  if (!(radius > 0.0) || points == 0 || len <= 0.5 * n * (double)f->length)
    return 0;
  return th / (double)points > SATF_IMPORT_SHELL_STRAND_WIDTH * radius;
}

/* Fits cluster batch[i] with its own control point count. */
static int fit_job(void *vctx, size_t i, int thread) {
  (void)thread;
  refine *r = vctx;
  int c = r->batch[i];
  satf_import_fit_params fp = *r->fp;
  fp.n_ctrl = r->ctrl[c];
  /* sparse strands: a cluster of one or a few is as thin as they are */
  if (r->half_thickness > 0.0f && r->half_thickness < fp.min_radius)
    fp.min_radius = r->half_thickness;
  if (fp.samples < 4 * fp.n_ctrl)
    fp.samples = 4 * fp.n_ctrl;
  satf_import_fit_free(&r->fits[c]);
  const int *m = r->g.idx + r->g.off[c];
  int n = r->g.off[c + 1] - r->g.off[c];
  if (satf_import_fit_cluster(r->s, m, n, &fp, &r->fits[c], &r->errs[c]))
    return 1;
  r->score[c] = satf_import_fit_score(&r->fits[c], r->rp);
  r->too_wide[c] = (unsigned char)strands_too_wide(r, c);
  return 0;
}

/* Splits cluster batch[i]: r->sides over its members' slots. */
static int split_job(void *vctx, size_t i, int thread) {
  (void)thread;
  refine *r = vctx;
  int c = r->batch[i];
  const int *m = r->g.idx + r->g.off[c];
  int n = r->g.off[c + 1] - r->g.off[c];
  r->split_ones[i] =
      split_k(r->s, m, n, r->split_want[i], r->sides + r->g.off[c]);
  return r->split_ones[i] < 0;
}

/* Density estimates of cluster batch[i] (as satf_import_fit_all does). */
static int density_job(void *vctx, size_t i, int thread) {
  (void)thread;
  refine *r = vctx;
  int c = (int)i;
  const int *m = r->g.idx + r->g.off[c];
  int n = r->g.off[c + 1] - r->g.off[c];
  satf_cluster *cl = NULL;
  satf_status st =
      satf_import_fit_cluster_create(&r->fits[c], &cl, &r->errs[c]);
  satf_import_projection proj;
  if (st == SATF_OK)
    st = satf_import_project(r->s, m, n, cl, &proj, &r->errs[c]);
  if (st == SATF_OK) {
    satf_import_estimate_density(&proj, &r->fits[c]);
    satf_import_width_from_thickness(r->s, m, n, &r->fits[c]);
    satf_import_projection_free(&proj);
  }
  satf_cluster_destroy(cl);
  return st != SATF_OK;
}

static satf_status run_jobs(refine *r, size_t count, satf_parallel_fn fn,
                            satf_error *err) {
  if (count == 0)
    return SATF_OK;
  if (satf_parallel_for(count, r->rp->threads, fn, r, NULL, NULL) == 0)
    return SATF_OK;
  for (int c = 0; c < r->cap; c++)
    if (r->errs[c].message[0])
      return satf_error_set(
          err, r->errs[c].status ? r->errs[c].status : SATF_ERR_INTERNAL, "%s",
          r->errs[c].message);
  return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
}

static int by_score(const void *pa, const void *pb, void *ctx) {
  const float *score = ctx;
  int a = *(const int *)pa, b = *(const int *)pb;
  if (score[a] != score[b])
    return score[a] < score[b] ? 1 : -1;
  return (a > b) - (a < b);
}

/* qsort_r is not C11: a small insertion sort keeps the order deterministic
 * (the failing clusters of a round are few next to the strands). */
static void sort_by_score(int *v, int n, float *score) {
  for (int i = 1; i < n; i++) {
    int x = v[i], j = i;
    while (j > 0 && by_score(&v[j - 1], &x, score) > 0) {
      v[j] = v[j - 1];
      j--;
    }
    v[j] = x;
  }
}

/* One round: fit what is stale, then give the failing clusters more
 * control points or split them. Returns 1 when something changed. */
static satf_status round_once(refine *r, int *changed, satf_error *err) {
  *changed = 0;
  satf_import_groups_free(&r->g);
  if (satf_import_groups_build(r->labels, r->n_strands, r->k, &r->g))
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  r->n_batch = 0;
  for (int c = 0; c < r->k; c++)
    if (r->state[c] == STALE)
      r->batch[r->n_batch++] = c;
  satf_status st = run_jobs(r, (size_t)r->n_batch, fit_job, err);
  if (st != SATF_OK)
    return st;
  for (int i = 0; i < r->n_batch; i++)
    r->state[r->batch[i]] = FITTED;
  /* the failing clusters, worst first */
  r->n_batch = 0;
  for (int c = 0; c < r->k; c++)
    if (r->state[c] == FITTED && (r->score[c] > 1.0f || sparse_group(r, c)))
      r->batch[r->n_batch++] = c;
  sort_by_score(r->batch, r->n_batch, r->score);
  /* those whose trajectory is what fails get more control points first */
  int split_n = 0, new_k = 0;
  for (int i = 0; i < r->n_batch; i++) {
    int c = r->batch[i];
    const satf_import_fit_measures *m = &r->fits[c].measures;
    float traj = m->trajectory[1] / r->rp->tolerance;
    int more = !r->ctrl_tried[c] && r->ctrl[c] < r->rp->max_ctrl &&
               traj > 1.0f && traj >= 0.999f * r->score[c] &&
               !sparse_group(r, c);
    if (more) {
      r->ctrl_tried[c] = r->ctrl[c];
      r->ctrl[c] =
          2 * r->ctrl[c] < r->rp->max_ctrl ? 2 * r->ctrl[c] : r->rp->max_ctrl;
      r->state[c] = STALE;
      *changed = 1;
      continue;
    }
    int n = r->g.off[c + 1] - r->g.off[c];
    if (n < 2) {
      r->state[c] = FINAL;
      continue;
    }
    /* clusters too wide for the tolerance shrink as the square root of
     * their strands: ask for about score^2 parts at once (fewer rounds,
     * fewer re-fits of the same strands) */
    float sc = r->score[c];
    int want =
        sc > 2.83f || sparse_group(r, c) ? SPLIT_MAX : (int)ceilf(sc * sc);
    want = want < 2 ? 2 : want > n ? n : want;
    if (r->k + new_k + want - 1 > r->rp->max_clusters)
      want = r->rp->max_clusters - r->k - new_k + 1;
    if (want < 2)
      break;
    r->split_want[split_n] = want;
    new_k += want - 1;
    r->batch[split_n++] = c;
  }
  r->n_batch = split_n;
  st = run_jobs(r, (size_t)split_n, split_job, err);
  if (st != SATF_OK)
    return st;
  for (int i = 0; i < split_n; i++) {
    int c = r->batch[i];
    int parts = r->split_ones[i];
    if (parts < 2) {
      r->state[c] = FINAL;
      continue;
    }
    /* part 0 keeps the index c, the others get new ones; every part keeps
     * the control points the cluster had */
    int first = r->k;
    r->k += parts - 1;
    for (int j = r->g.off[c]; j < r->g.off[c + 1]; j++)
      if (r->sides[j])
        r->labels[r->g.idx[j]] = first + r->sides[j] - 1;
    for (int q = 0; q < parts; q++) {
      int cc = q == 0 ? c : first + q - 1;
      r->ctrl[cc] = r->ctrl[c];
      r->ctrl_tried[cc] = 0;
      r->state[cc] = STALE;
    }
    *changed = 1;
  }
  return SATF_OK;
}

static void refine_free(refine *r) {
  free(r->ctrl);
  free(r->state);
  free(r->score);
  free(r->ctrl_tried);
  free(r->too_wide);
  free(r->errs);
  free(r->batch);
  free(r->sides);
  free(r->split_ones);
  free(r->split_want);
  satf_import_groups_free(&r->g);
}

satf_status satf_import_refine(const satf_strand_set *s,
                               const satf_import_cluster_params *cp,
                               const satf_import_refine_params *rp,
                               const satf_import_fit_params *fp, int *labels,
                               int *n_clusters, satf_import_fit **fits,
                               satf_import_progress_fn progress,
                               void *progress_ctx, satf_error *err) {
  *fits = NULL;
  *n_clusters = 0;
  int n = satf_strand_set_count(s);
  if (!(rp->tolerance > 0.0f) || !isfinite(rp->tolerance) ||
      !(rp->spacing >= 0.0f) || !(rp->area_ratio >= 0.0f) ||
      !(rp->min_aspect >= 0.0f) || rp->initial < 1 || rp->max_clusters < 1 ||
      rp->max_clusters > SATF_IMPORT_MAX_CLUSTERS ||
      rp->max_ctrl < fp->n_ctrl || rp->max_ctrl > 64 || n < 1)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "clustering: tolerance %g (> 0), %d initial and at "
                          "most %d clusters (1..%d), up to %d control points "
                          "(%d..64), %d strands (>= 1)",
                          (double)rp->tolerance, rp->initial, rp->max_clusters,
                          SATF_IMPORT_MAX_CLUSTERS, rp->max_ctrl, fp->n_ctrl,
                          n);
  satf_import_cluster_params kp = *cp;
  kp.clusters = rp->initial < rp->max_clusters ? rp->initial : rp->max_clusters;
  kp.threads = rp->threads;
  int k0 = 0;
  satf_status st =
      satf_import_kmeans(s, &kp, labels, &k0, NULL, NULL, NULL, err);
  if (st != SATF_OK)
    return st;
  refine r;
  memset(&r, 0, sizeof r);
  r.s = s;
  r.rp = rp;
  r.fp = fp;
  r.n_strands = n;
  double th_sum = 0.0;
  size_t th_count = 0;
  for (int i = 0; i < n; i++) {
    const float *th = satf_strand_set_thickness(s, i);
    int m = satf_strand_set_points(s, i);
    for (int k = 0; th && k < m; k++)
      th_sum += th[k];
    th_count += th ? (size_t)m : 0;
  }
  r.half_thickness = th_count ? (float)(0.5 * th_sum / (double)th_count) : 0.0f;
  r.k = k0;
  r.cap = rp->max_clusters > k0 ? rp->max_clusters : k0;
  r.labels = labels;
  size_t cap = (size_t)r.cap;
  r.fits = calloc(cap, sizeof *r.fits);
  r.ctrl = malloc(cap * sizeof(int));
  r.state = calloc(cap, sizeof(int));
  r.score = calloc(cap, sizeof(float));
  r.ctrl_tried = calloc(cap, sizeof(int));
  r.too_wide = calloc(cap, 1);
  r.errs = calloc(cap, sizeof *r.errs);
  r.batch = malloc(cap * sizeof(int));
  r.sides = malloc((size_t)n * sizeof(int));
  r.split_ones = malloc(cap * sizeof(int));
  r.split_want = malloc(cap * sizeof(int));
  if (!r.fits || !r.ctrl || !r.state || !r.score || !r.ctrl_tried ||
      !r.too_wide || !r.errs || !r.batch || !r.sides || !r.split_ones ||
      !r.split_want) {
    free(r.fits);
    refine_free(&r);
    return satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  }
  for (size_t c = 0; c < cap; c++)
    r.ctrl[c] = fp->n_ctrl;
  int changed = 1;
  while (st == SATF_OK && changed) {
    st = round_once(&r, &changed, err);
    if (progress && st == SATF_OK) {
      int pass = 0;
      for (int c = 0; c < r.k; c++)
        pass += r.state[c] != STALE && r.score[c] <= 1.0f;
      progress(progress_ctx, (size_t)pass, (size_t)r.k);
    }
  }
  if (st == SATF_OK) {
    satf_import_groups_free(&r.g);
    if (satf_import_groups_build(labels, n, r.k, &r.g))
      st = satf_error_set(err, SATF_ERR_NOMEM, "clustering: out of memory");
  }
  if (st == SATF_OK)
    st = run_jobs(&r, (size_t)r.k, density_job, err);
  if (st != SATF_OK) {
    for (int c = 0; c < r.cap; c++)
      satf_import_fit_free(&r.fits[c]);
    free(r.fits);
    refine_free(&r);
    return st;
  }
  refine_free(&r);
  *fits = r.fits;
  *n_clusters = r.k;
  return SATF_OK;
}
