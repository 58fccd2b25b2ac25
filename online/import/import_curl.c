/* import_curl.c - how far a strand curls about its own course. A helix of
 * radius rho (curly hair) stays about rho from any trajectory a cluster of
 * such strands can have (their phases differ), and its fibres cross that
 * trajectory at the helix's angle: a cluster whose strands curl gets that
 * angle in the scene (satf_scene_density.curl), which the physical
 * shading spreads the fibres' M_p over. */
#include <math.h>
#include <stdlib.h>

#include "import_internal.h"
#include "satf/common.h"

/* Samples along a strand, and the moving average's half-window in them:
 * 8 of 32 intervals either side, half the strand in all. A helix of 2.5-4
 * turns along the strand (the generated curls) is averaged over 1.25-2
 * turns, to about its axis, so the distance comes to about its radius
 * (1.42 for a radius of 1.2 over 4 turns, test_strand_curl). */
enum { CURL_SAMPLES = 33, CURL_HALF = 8 };

/* A strand curls when its median tangent crosses its course (the moving
 * average's) at 20 degrees or more: the generated curls' helices cross at
 * 27-63 degrees (44 median), the shared ponytail's wavy strands at under
 * 16 (their clusters' p90). Below it the strand is wavy, not curly: its
 * waves are its cluster's to follow, and their spread lies within the
 * lobes' own width (the cone given to every cluster of the ponytail moved
 * its SSIM4 against Cycles by under 0.001 and cost the maps 35 ms a
 * frame, docs/import.md). */
#define CURL_MIN_COS 0.93969262f /* cos 20 degrees */

float satf_import_strand_curl(const satf_strand_set *s, int i) {
  float p[3 * CURL_SAMPLES], m[3 * CURL_SAMPLES], d[CURL_SAMPLES];
  satf_import_resample(s, i, CURL_SAMPLES, p);
  for (int k = 0; k < CURL_SAMPLES; k++) {
    /* the window shrinks evenly at the ends: the root and tip are their
     * own average */
    int h = k < CURL_HALF ? k : CURL_SAMPLES - 1 - k;
    h = h < CURL_HALF ? h : CURL_HALF;
    double a[3] = {0.0, 0.0, 0.0};
    for (int j = k - h; j <= k + h; j++)
      for (int c = 0; c < 3; c++)
        a[c] += p[3 * j + c];
    double e = 0.0;
    for (int c = 0; c < 3; c++) {
      m[3 * k + c] = (float)(a[c] / (2 * h + 1));
      double x = p[3 * k + c] - m[3 * k + c];
      e += x * x;
    }
    d[k] = (float)sqrt(e);
  }
  /* the cosine of each segment's angle to the course over it */
  float cosines[CURL_SAMPLES - 1];
  for (int k = 0; k + 1 < CURL_SAMPLES; k++) {
    double t[3], u[3], tt = 0.0, uu = 0.0, tu = 0.0;
    for (int c = 0; c < 3; c++) {
      t[c] = p[3 * (k + 1) + c] - p[3 * k + c];
      u[c] = m[3 * (k + 1) + c] - m[3 * k + c];
      tt += t[c] * t[c];
      uu += u[c] * u[c];
      tu += t[c] * u[c];
    }
    cosines[k] = tt > 0.0 && uu > 0.0 ? (float)(tu / sqrt(tt * uu)) : 1.0f;
  }
  float pc[3];
  satf_import_percentiles(cosines, CURL_SAMPLES - 1, pc);
  if (pc[0] > CURL_MIN_COS)
    return 0.0f;
  satf_import_percentiles(d, CURL_SAMPLES, pc); /* p90, as the fit's */
  return pc[1];
}

float satf_import_members_curl(const float *curl, const int *members, int n) {
  if (n < 2)
    return 0.0f; /* one strand: its own trajectory follows its curl */
  float *v = malloc((size_t)n * sizeof *v), pc[3] = {0.0f, 0.0f, 0.0f};
  if (!v)
    return 0.0f;
  for (int i = 0; i < n; i++)
    v[i] = curl[members[i]];
  satf_import_percentiles(v, (size_t)n, pc);
  free(v);
  return pc[0];
}

typedef struct curl_ctx {
  const satf_strand_set *s;
  satf_import_groups g;
  float *strand;
  satf_import_fit *fits;
} curl_ctx;

static int strand_job(void *vctx, size_t i, int thread) {
  (void)thread;
  curl_ctx *c = vctx;
  c->strand[i] = satf_import_strand_curl(c->s, (int)i);
  return 0;
}

static int cluster_job(void *vctx, size_t i, int thread) {
  (void)thread;
  curl_ctx *c = vctx;
  c->fits[i].curl = satf_import_members_curl(c->strand, c->g.idx + c->g.off[i],
                                             c->g.off[i + 1] - c->g.off[i]);
  return 0;
}

int satf_import_fits_curl(const satf_strand_set *s, const int *labels,
                          satf_import_fit *fits, int n, int threads) {
  int ns = satf_strand_set_count(s);
  curl_ctx c = {s, {NULL, NULL}, NULL, fits};
  c.strand = malloc((size_t)(ns > 0 ? ns : 1) * sizeof(float));
  int rc = -1;
  if (c.strand && satf_import_groups_build(labels, ns, n, &c.g) == 0)
    rc = satf_parallel_for((size_t)ns, threads, strand_job, &c, NULL, NULL) ||
                 satf_parallel_for((size_t)n, threads, cluster_job, &c, NULL,
                                   NULL)
             ? -1
             : 0;
  satf_import_groups_free(&c.g);
  free(c.strand);
  return rc;
}
