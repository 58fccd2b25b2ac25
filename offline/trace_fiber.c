/* trace_fiber.c - fibre records (format version 2): 2-D Monte
 * Carlo path tracing of a sector's strands as circular fibres in their
 * normal plane, with the d'Eon/Chiang azimuthal scattering of one fibre
 * (paper 003, satf/fiber.h: A_p N_p at theta_i = theta_o = 0).
 *
 * Each record sample shoots sub-rays across its footprint (the ray layout
 * of satf/db.h "Record layout"). At every fibre a path meets, next-event
 * estimation looks towards every light azimuth of the grid at once (one eye
 * path serves all n_light records): A_p(h) N_p(phi) times the light's
 * visibility through the other fibres (light leaving the sector is not
 * occluded). The path then goes on towards one of the occluded light
 * azimuths, drawn by the response (vertex_step), to the next fibre, until
 * nothing is occluded or max_bounces. Absorption is kept per level (one
 * throughput per sigma_a) along one sampled geometry, so one trace serves
 * every hair colour.
 *
 * Conventions. Fibre k has centre c and radius r. A ray travelling along d
 * meets it at x; the outgoing direction of the fibre model is wo = -d, and
 * h (satf/fiber.h) is the hit's coordinate along (sin phi_o, -cos phi_o)
 * over r. A ray only interacts with a fibre it enters from outside, so
 * overlapping fibres (strands are placed independently) do not trap rays.
 * Light visibility, and a scattered path, start from the fibre's centre,
 * ignoring the fibre itself (the far-field fibre model says where light
 * goes, not where on the fibre it leaves): the same rays for both, which is
 * what conserves energy. Scattered paths travel along the light azimuths
 * of the grid. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/fiber.h"
#include "satf/math.h"
#include "satf/offline.h"

#define STREAM_FIBER 0xF1BE7ull

/* ---- fibres binned across a direction ----
 * For direction u (towards a light or the viewer) the fibres are binned by
 * their coordinate along e = u rotated by +90 degrees, each bin sorted by
 * depth along u: a ray along u (or against it) only meets the fibres of its
 * bin. */
typedef struct binned {
  float d; /* centre depth along u */
  int k;   /* fibre index */
} binned;

typedef struct dir_index {
  float u[2], e[2];
  float lo, inv_bin;
  int nbins;
  int *start; /* nbins + 1 */
  binned *items;
} dir_index;

typedef struct fiber_geo {
  int n;
  const float *f; /* x, y, r per fibre */
  float rmax;
} fiber_geo;

static int cmp_binned(const void *a, const void *b) {
  const binned *x = a, *y = b;
  if (x->d != y->d)
    return x->d < y->d ? -1 : 1;
  return x->k - y->k; /* a total order: qsort is not stable */
}

static void bin_range(const dir_index *di, float p, float r, int *b0, int *b1) {
  *b0 = (int)floorf((p - r - di->lo) * di->inv_bin);
  *b1 = (int)floorf((p + r - di->lo) * di->inv_bin);
  if (*b0 < 0)
    *b0 = 0;
  if (*b1 > di->nbins - 1)
    *b1 = di->nbins - 1;
}

static int dir_index_build(dir_index *di, const fiber_geo *g, float theta) {
  memset(di, 0, sizeof *di);
  di->u[0] = cosf(theta);
  di->u[1] = sinf(theta);
  di->e[0] = -di->u[1];
  di->e[1] = di->u[0];
  float lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < g->n; k++) {
    const float *f = g->f + 3 * k;
    float p = f[0] * di->e[0] + f[1] * di->e[1];
    lo = p - f[2] < lo ? p - f[2] : lo;
    hi = p + f[2] > hi ? p + f[2] : hi;
  }
  if (g->n == 0) {
    lo = 0.0f;
    hi = 1.0f;
  }
  float bw = g->rmax > 1e-6f ? g->rmax : 1e-3f;
  di->lo = lo;
  di->inv_bin = 1.0f / bw;
  di->nbins = (int)((hi - lo) / bw) + 1;
  if (di->nbins > 65536) {
    di->nbins = 65536;
    di->inv_bin = (float)di->nbins / (hi - lo) * 0.999f;
  }
  di->start = calloc((size_t)di->nbins + 1, sizeof(int));
  if (!di->start)
    return -1;
  for (int k = 0; k < g->n; k++) {
    const float *f = g->f + 3 * k;
    int b0, b1;
    bin_range(di, f[0] * di->e[0] + f[1] * di->e[1], f[2], &b0, &b1);
    for (int b = b0; b <= b1; b++)
      di->start[b + 1]++;
  }
  for (int b = 0; b < di->nbins; b++)
    di->start[b + 1] += di->start[b];
  di->items = malloc(((size_t)di->start[di->nbins] + 1) * sizeof(binned));
  int *fill = malloc((size_t)di->nbins * sizeof(int));
  if (!di->items || !fill) {
    free(fill);
    return -1;
  }
  memcpy(fill, di->start, (size_t)di->nbins * sizeof(int));
  for (int k = 0; k < g->n; k++) {
    const float *f = g->f + 3 * k;
    int b0, b1;
    bin_range(di, f[0] * di->e[0] + f[1] * di->e[1], f[2], &b0, &b1);
    float d = f[0] * di->u[0] + f[1] * di->u[1];
    for (int b = b0; b <= b1; b++)
      di->items[fill[b]++] = (binned){d, k};
  }
  free(fill);
  for (int b = 0; b < di->nbins; b++)
    qsort(di->items + di->start[b], (size_t)(di->start[b + 1] - di->start[b]),
          sizeof(binned), cmp_binned);
  return 0;
}

static void dir_index_free(dir_index *di) {
  free(di->start);
  free(di->items);
}

/* The nearest fibre other than `skip` that the ray from x along di->u
 * enters (from outside) ahead of x, and the distance t to its entry; -1
 * when the ray leaves the sector. */
static int occluder(const dir_index *di, const fiber_geo *g, const float x[2],
                    int skip, float *t_hit) {
  float p = x[0] * di->e[0] + x[1] * di->e[1];
  int b = (int)floorf((p - di->lo) * di->inv_bin);
  if (b < 0 || b >= di->nbins)
    return -1;
  float d0 = x[0] * di->u[0] + x[1] * di->u[1];
  int end = di->start[b + 1];
  /* an entry ahead needs a centre ahead: skip depths <= d0 */
  int lo = di->start[b], hi = end;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (di->items[mid].d <= d0)
      lo = mid + 1;
    else
      hi = mid;
  }
  int best = -1;
  float best_t = INFINITY;
  for (int i = lo; i < end; i++) {
    float tc = di->items[i].d - d0;
    if (tc - g->rmax >= best_t)
      break; /* sorted by depth: nothing nearer follows */
    int k = di->items[i].k;
    if (k == skip)
      continue;
    const float *f = g->f + 3 * k;
    float off = (f[0] - x[0]) * di->e[0] + (f[1] - x[1]) * di->e[1];
    float r2 = f[2] * f[2] - off * off;
    if (r2 <= 0.0f)
      continue;
    float t = tc - sqrtf(r2);
    if (t > 0.0f && (t < best_t || (t == best_t && k < best))) {
      best_t = t;
      best = k;
    }
  }
  *t_hit = best_t;
  return best;
}

/* The first fibre a ray at screen coordinate p (along di->e), coming from
 * far along +u and travelling along -u, enters; -1 if none. */
static int first_hit(const dir_index *di, const fiber_geo *g, float p,
                     float x[2]) {
  int b = (int)floorf((p - di->lo) * di->inv_bin);
  if (b < 0 || b >= di->nbins)
    return -1;
  int best = -1;
  float best_d = -INFINITY;
  for (int i = di->start[b]; i < di->start[b + 1]; i++) {
    int k = di->items[i].k;
    const float *f = g->f + 3 * k;
    float off = f[0] * di->e[0] + f[1] * di->e[1] - p;
    float r2 = f[2] * f[2] - off * off;
    if (r2 <= 0.0f)
      continue;
    float d = di->items[i].d + sqrtf(r2); /* the surface facing the viewer */
    if (d > best_d || (d == best_d && k < best)) {
      best_d = d;
      best = k;
    }
  }
  if (best >= 0) {
    x[0] = p * di->e[0] + best_d * di->u[0];
    x[1] = p * di->e[1] + best_d * di->u[1];
  }
  return best;
}

/* ---- one trace ---- */

typedef struct fiber_tracer {
  const satf_fiber_trace_params *p;
  fiber_geo g;
  int n_light, width, channels;
  float s;        /* N_p logistic scale */
  float dphi;     /* 2 pi / n_light: the lights' quadrature weight */
  dir_index *lit; /* n_light light indices */
  float *theta_l;
  /* Scratch of one vertex, per light: */
  float *acc;   /* n_light x channels: one sample's sums */
  float *np;    /* n_light x 3: N_0, N_1, N_2 towards the light */
  float *f0;    /* response at level 0 towards an occluded light, else 0 */
  int *occ;     /* the fibre occluding the light, -1 when visible */
  float *occ_t; /* and the distance to its entry */
} fiber_tracer;

/* Everything one fibre interaction needs. */
typedef struct vertex {
  int k;
  float phi_o, h, gamma_o, gamma_t;
  float ap[SATF_DB_LEVELS_MAX][SATF_FIBER_LOBES];
} vertex;

static void vertex_init(const fiber_tracer *t, vertex *v, int k,
                        const float x[2], const float d[2]) {
  const float *f = t->g.f + 3 * k;
  float wo[2] = {-d[0], -d[1]};
  float n[2] = {(x[0] - f[0]) / f[2], (x[1] - f[1]) / f[2]};
  /* satf/fiber.h: h along (sin phi_o, -cos phi_o) */
  float h = n[0] * wo[1] - n[1] * wo[0];
  h = h < -1.0f ? -1.0f : h > 1.0f ? 1.0f : h;
  v->k = k;
  v->phi_o = atan2f(wo[1], wo[0]);
  v->h = h;
  v->gamma_o = asinf(h);
  v->gamma_t = asinf(h / t->p->eta); /* theta_o = 0: eta' = eta */
  for (int l = 0; l < t->p->levels; l++) {
    float T = satf_fiber_transmittance(t->p->sigma_a[l], h, t->p->eta, 0.0f);
    satf_fiber_ap(1.0f, t->p->eta, h, T, v->ap[l]);
  }
}

/* sum_p A_p N_p of level l towards a light with N_p = np[0..2] and the
 * remainder's N_3 = 1 / (2 pi) (pbrt: azimuthally uniform). */
static float response(const vertex *v, int l, const float *np) {
  const float *a = v->ap[l];
  return a[0] * np[0] + a[1] * np[1] + a[2] * np[2] +
         a[3] * (1.0f / SATF_TWO_PI_F);
}

/* One fibre interaction. Next-event estimation towards every light azimuth:
 * a visible light gets A_p N_p (the first vertex split into R, TT, TRT;
 * later ones into MS with the path's throughput per level). The path goes
 * on towards one of the occluded lights, drawn by the level-0 response, to
 * the fibre that occludes it: the scattered light that does not leave the
 * sector at once. Its throughput takes the occluded share of the response,
 * so with nothing absorbed what a path deposits telescopes to
 * 1 - prod_v (1 - visible share at v): energy is conserved by construction
 * up to the lights' quadrature of N_p (2-D white furnace). Returns the next
 * fibre and its entry x along d, or -1. */
static int vertex_step(const fiber_tracer *t, const vertex *v, int bounce,
                       float *thr, satf_rng *rng, float x[2], float d[2]) {
  const float *c = t->g.f + 3 * v->k;
  int K = t->p->levels, C = t->channels;
  float occ_sum = 0.0f;
  for (int il = 0; il < t->n_light; il++) {
    float phi = t->theta_l[il] - v->phi_o;
    float *np = t->np + 3 * il;
    for (int p = 0; p < 3; p++)
      np[p] = satf_fiber_np(phi, p, t->s, v->gamma_o, v->gamma_t);
    t->occ[il] = occluder(&t->lit[il], &t->g, c, v->k, &t->occ_t[il]);
    t->f0[il] = 0.0f;
    if (t->occ[il] >= 0) {
      t->f0[il] = response(v, 0, np);
      occ_sum += t->f0[il];
      continue;
    }
    float *a = t->acc + (size_t)il * (size_t)C;
    if (bounce == 0) {
      a[SATF_DB_CH_R] += v->ap[0][0] * np[0];
      for (int l = 0; l < K; l++) {
        a[SATF_DB_CH_TT(l)] += v->ap[l][1] * np[1];
        a[SATF_DB_CH_TRT(l, K)] +=
            v->ap[l][2] * np[2] + v->ap[l][3] * (1.0f / SATF_TWO_PI_F);
      }
    } else {
      for (int l = 0; l < K; l++)
        a[SATF_DB_CH_MS(l, K)] += thr[l] * response(v, l, np);
    }
  }
  if (bounce + 1 >= t->p->max_bounces || !(occ_sum > 0.0f))
    return -1;
  float u = (float)satf_rng_uniform(rng) * occ_sum;
  int pick = -1;
  for (int il = 0; il < t->n_light; il++) {
    if (!(t->f0[il] > 0.0f))
      continue;
    pick = il;
    if (u < t->f0[il])
      break;
    u -= t->f0[il];
  }
  if (pick < 0)
    return -1;
  const float *np = t->np + 3 * pick;
  float f0 = t->f0[pick];
  /* unbiased per level: f_l / pdf, pdf = f0 / (occ_sum * dphi) */
  for (int l = 0; l < K; l++)
    thr[l] *= response(v, l, np) / f0 * occ_sum * t->dphi;
  /* Russian roulette once every level carries less than 5%: unbiased,
   * and it ends paths that white (unabsorbed) levels would follow until
   * nothing is occluded. */
  float most = 0.0f;
  for (int l = 0; l < K; l++)
    most = thr[l] > most ? thr[l] : most;
  if (most < 0.05f) {
    float q = most / 0.05f;
    if (!((float)satf_rng_uniform(rng) < q))
      return -1;
    for (int l = 0; l < K; l++)
      thr[l] /= q;
  }
  const dir_index *di = &t->lit[pick];
  d[0] = di->u[0];
  d[1] = di->u[1];
  x[0] = c[0] + t->occ_t[pick] * d[0];
  x[1] = c[1] + t->occ_t[pick] * d[1];
  return t->occ[pick];
}

/* One eye path entering fibre k at x along d; adds to t->acc. */
static void trace_path(const fiber_tracer *t, int k, float x[2], float d[2],
                       satf_rng *rng) {
  float thr[SATF_DB_LEVELS_MAX];
  for (int l = 0; l < t->p->levels; l++)
    thr[l] = 1.0f;
  vertex v;
  for (int bounce = 0; k >= 0; bounce++) {
    vertex_init(t, &v, k, x, d);
    k = vertex_step(t, &v, bounce, thr, rng, x, d);
  }
}

static satf_status tracer_init(fiber_tracer *t, const satf_sector *sec,
                               const satf_fiber_trace_params *p, int width,
                               int n_light, satf_error *err) {
  memset(t, 0, sizeof *t);
  t->p = p;
  t->g.n = sec->fiber_count;
  t->g.f = sec->fibers;
  for (int k = 0; k < t->g.n; k++)
    t->g.rmax =
        sec->fibers[3 * k + 2] > t->g.rmax ? sec->fibers[3 * k + 2] : t->g.rmax;
  t->n_light = n_light;
  t->width = width;
  t->channels = SATF_DB_FIBER_CHANNELS(p->levels);
  t->s = satf_fiber_azimuthal_scale(p->beta_n);
  t->lit = calloc((size_t)n_light, sizeof(dir_index));
  t->theta_l = malloc((size_t)n_light * sizeof(float));
  t->dphi = SATF_TWO_PI_F / (float)n_light;
  t->acc = malloc((size_t)n_light * (size_t)t->channels * sizeof(float));
  t->np = malloc(3 * (size_t)n_light * sizeof(float));
  t->f0 = malloc((size_t)n_light * sizeof(float));
  t->occ = malloc((size_t)n_light * sizeof(int));
  t->occ_t = malloc((size_t)n_light * sizeof(float));
  if (!t->lit || !t->theta_l || !t->acc || !t->np || !t->f0 || !t->occ ||
      !t->occ_t)
    return satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate fibre tracer");
  for (int il = 0; il < n_light; il++) {
    t->theta_l[il] = SATF_TWO_PI_F * (float)il / (float)n_light;
    if (dir_index_build(&t->lit[il], &t->g, t->theta_l[il]) != 0)
      return satf_error_set(err, SATF_ERR_NOMEM,
                            "cannot allocate fibre tracer");
  }
  return SATF_OK;
}

static void tracer_free(fiber_tracer *t) {
  for (int il = 0; t->lit && il < t->n_light; il++)
    dir_index_free(&t->lit[il]);
  free(t->lit);
  free(t->theta_l);
  free(t->acc);
  free(t->np);
  free(t->f0);
  free(t->occ);
  free(t->occ_t);
}

/* Record sample j of view iv: sums its sub-rays into t->acc, returns the
 * number that hit. */
static int trace_sample(const fiber_tracer *t, const dir_index *view,
                        float pmin, float pmax, int j, satf_rng *rng) {
  int S = t->p->sub_rays, hits = 0;
  float dp = (pmax - pmin) / (float)t->width;
  memset(t->acc, 0, (size_t)t->n_light * (size_t)t->channels * sizeof(float));
  for (int s = 0; s < S; s++) {
    /* stratified across the footprint */
    float u = ((float)s + (float)satf_rng_uniform(rng)) / (float)S;
    float x[2], d[2] = {-view->u[0], -view->u[1]};
    int k = first_hit(view, &t->g, pmin + ((float)j + u) * dp, x);
    if (k < 0)
      continue;
    hits++;
    trace_path(t, k, x, d, rng);
  }
  return hits;
}

satf_status satf_trace_fiber_all(const satf_sector *sector,
                                 const satf_fiber_trace_params *p, int width,
                                 int n_view, int n_light, uint64_t seed,
                                 uint64_t sample, float *out, satf_error *err) {
  satf_status st = satf_fiber_trace_params_check(p, err);
  if (st != SATF_OK)
    return st;
  if (width < 1 || width > 4096 || n_view < 1 || n_light < 1 || n_view > 4096 ||
      n_light > 4096)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "fibre trace: width %d, angles %d x %d out of range "
                          "[1, 4096]",
                          width, n_view, n_light);
  if (sector->fiber_failed)
    return satf_error_set(err, SATF_ERR_NOMEM,
                          "the sector's fibre list is incomplete (out of "
                          "memory while placing strands)");
  fiber_tracer t;
  st = tracer_init(&t, sector, p, width, n_light, err);
  int C = t.channels, K = p->levels;
  size_t rec = (size_t)C * (size_t)width;
  float inv = 1.0f / (float)p->sub_rays;
  for (int iv = 0; st == SATF_OK && iv < n_view; iv++) {
    float theta_v = SATF_TWO_PI_F * (float)iv / (float)n_view;
    dir_index own, *view = &own;
    if (n_view == n_light) {
      view = &t.lit[iv]; /* the same azimuth grid */
    } else if (dir_index_build(&own, &t.g, theta_v) != 0) {
      dir_index_free(&own);
      st = satf_error_set(err, SATF_ERR_NOMEM, "cannot allocate fibre tracer");
      break;
    }
    float pmin, pmax;
    satf_trace_extent(&sector->shape, theta_v, &pmin, &pmax);
    for (int j = 0; j < width; j++) {
      satf_rng rng;
      uint64_t stream =
          ((sample * (uint64_t)n_view + (uint64_t)iv) * (uint64_t)width) +
          (uint64_t)j;
      satf_rng_seed(&rng, seed ^ STREAM_FIBER, stream);
      int hits = trace_sample(&t, view, pmin, pmax, j, &rng);
      for (int il = 0; il < n_light; il++) {
        float *r = out + ((size_t)iv * (size_t)n_light + (size_t)il) * rec;
        const float *a = t.acc + (size_t)il * (size_t)C;
        for (int c = SATF_DB_CH_R; c < C; c++)
          r[(size_t)c * (size_t)width + (size_t)j] = a[c] * inv;
        r[(size_t)SATF_DB_CH_ALPHA * (size_t)width + (size_t)j] =
            (float)hits * inv;
        r[j] = (a[SATF_DB_CH_R] + a[SATF_DB_CH_TT(0)] +
                a[SATF_DB_CH_TRT(0, K)] + a[SATF_DB_CH_MS(0, K)]) *
               inv;
      }
    }
    if (view == &own)
      dir_index_free(&own);
  }
  tracer_free(&t);
  return st;
}
