/* bench_fiber_levels.c - how well a set of absorption levels serves every
 * hair colour: fibre records of a few sectors are traced at the candidate
 * levels and at a fine sweep of sigma_a on the same paths (the geometry
 * depends only on the first level, sigma_a = 0 in both), and the renderer's
 * log-linear interpolation in sigma between the levels (extrapolation past
 * the last) is compared with the traced values. Prints, per lobe, the
 * relative error sum |interpolated - traced| / sum traced over every record
 * sample of the sectors, the worst over the sweep and where.
 *
 * usage: bench_fiber_levels [L1,L2,...]   (levels after 0; default the
 * database default) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/offline.h"

#define W 16
#define NV 8
#define NL 16
#define SECTORS 6

static float *trace(const satf_sector *sec, const satf_fiber_trace_params *p,
                    uint64_t sample) {
  size_t n = (size_t)NV * NL * W * SATF_DB_FIBER_CHANNELS(p->levels);
  float *out = malloc(n * sizeof(float));
  satf_error err;
  if (!out || satf_trace_fiber_all(sec, p, W, NV, NL, 1, sample, out, &err)) {
    fprintf(stderr, "bench_fiber_levels: %s\n", out ? err.message : "memory");
    exit(1);
  }
  return out;
}

/* Channel value of lobe (0 TT, 1 TRT, 2 MS) at level k, record r, sample j */
static float value(const float *out, const satf_fiber_trace_params *p, int r,
                   int lobe, int k, int j) {
  int K = p->levels;
  int ch = lobe == 0   ? SATF_DB_CH_TT(k)
           : lobe == 1 ? SATF_DB_CH_TRT(k, K)
                       : SATF_DB_CH_MS(k, K);
  return out[((size_t)r * SATF_DB_FIBER_CHANNELS(K) + (size_t)ch) * W + j];
}

/* The renderer's interpolation: log-linear in sigma between the bracketing
 * levels (linear when one is 0), extrapolated from the last two. */
static double interp(const float *lv, int K, const double *v, double sigma) {
  int a = 0;
  while (a + 2 < K && sigma > lv[a + 1])
    a++;
  double t = (sigma - lv[a]) / (lv[a + 1] - lv[a]);
  if (v[a] > 0.0 && v[a + 1] > 0.0)
    return exp((1.0 - t) * log(v[a]) + t * log(v[a + 1]));
  double r = (1.0 - t) * v[a] + t * v[a + 1];
  return r > 0.0 ? r : 0.0;
}

int main(int argc, char **argv) {
  satf_fiber_trace_params lv = satf_fiber_trace_params_default();
  lv.sub_rays = 4;
  if (argc > 1) {
    lv.levels = 1;
    for (char *c = argv[1]; *c && lv.levels < SATF_DB_LEVELS_MAX;) {
      char *end;
      lv.sigma_a[lv.levels++] = strtof(c, &end);
      c = *end ? end + 1 : end;
    }
  }
  const double sweep[] = {0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5,  2.0,
                          3.0, 4.0, 5.0,  6.5, 8.0,  10., 12.5, 16.};
  const int ns = (int)(sizeof sweep / sizeof sweep[0]);
  double worst[3] = {0}, at[3] = {0};
  satf_build_params bp = satf_build_params_default();
  printf("levels:");
  for (int k = 0; k < lv.levels; k++)
    printf(" %g", (double)lv.sigma_a[k]);
  printf("\nsigma   TT err   TRT err  MS err   (sum |interp - traced| / sum "
         "traced, %d sectors)\n",
         SECTORS);
  for (int si = 0; si < ns; si++) {
    double num[3] = {0}, den[3] = {0};
    satf_fiber_trace_params one = lv;
    one.levels = 2;
    one.sigma_a[0] = 0.0f;
    one.sigma_a[1] = (float)sweep[si];
    for (int s = 0; s < SECTORS; s++) {
      uint64_t index = (uint64_t)(3 * s + 1);
      satf_sector *sec = NULL;
      if (satf_build_sector(&bp, bp.seed, index, &sec, NULL) != SATF_OK)
        return 1;
      float *a = trace(sec, &lv, index), *b = trace(sec, &one, index);
      for (int r = 0; r < NV * NL; r++)
        for (int j = 0; j < W; j++)
          for (int lobe = 0; lobe < 3; lobe++) {
            double v[SATF_DB_LEVELS_MAX];
            for (int k = 0; k < lv.levels; k++)
              v[k] = value(a, &lv, r, lobe, k, j);
            double want = value(b, &one, r, lobe, 1, j);
            num[lobe] +=
                fabs(interp(lv.sigma_a, lv.levels, v, sweep[si]) - want);
            den[lobe] += want;
          }
      free(a);
      free(b);
      satf_sector_destroy(sec);
    }
    printf("%-7g", sweep[si]);
    for (int lobe = 0; lobe < 3; lobe++) {
      double e = den[lobe] > 0.0 ? num[lobe] / den[lobe] : 0.0;
      printf(" %-8.4f", e);
      if (e > worst[lobe]) {
        worst[lobe] = e;
        at[lobe] = sweep[si];
      }
    }
    printf("\n");
  }
  printf("worst: TT %.4f (sigma %g), TRT %.4f (sigma %g), MS %.4f (sigma "
         "%g)\n",
         worst[0], at[0], worst[1], at[1], worst[2], at[2]);
  return 0;
}
