/* bench_db - offline-phase benchmark (not a test): HRIRs/s on 1 thread and
 * on all threads, their ratio, and SATF look-ups/s per core.
 * usage: bench_db [SAMPLES] (default 64 samples of the default 32x32x32). */
#include <stdio.h>
#include <stdlib.h>

#include "satf/common.h"
#include "satf/offline.h"

static double build_rate(const satf_build_params *p, int threads,
                         satf_db **keep) {
  double t0 = satf_now_seconds();
  satf_db *db = NULL;
  satf_error err;
  if (satf_build(p, threads, NULL, NULL, &db, &err) != SATF_OK) {
    fprintf(stderr, "bench_db: %s\n", err.message);
    exit(1);
  }
  double dt = satf_now_seconds() - t0;
  if (keep)
    *keep = db;
  else
    satf_db_destroy(db);
  return (double)p->samples * p->n_view * p->n_light / dt;
}

/* Random queries jump across the whole database (worst case for caches);
 * coherent ones drift slowly, as neighbouring HSVs of a shell do. */
static double lookup_rate(const satf_db *db, int k, int n, int coherent) {
  satf_rng rng;
  satf_rng_seed(&rng, 1, 1);
  float lo[3], hi[3], re[64], al[64];
  satf_db_feature_range(db, lo, hi);
  float(*q)[5] = malloc((size_t)n * sizeof *q);
  for (int i = 0; i < n; i++) {
    for (int a = 0; a < 3; a++)
      q[i][a] = lo[a] + (hi[a] - lo[a]) * (float)satf_rng_uniform(&rng);
    q[i][3] = (float)satf_rng_range(&rng, 0, 6.283);
    q[i][4] = (float)satf_rng_range(&rng, 0, 6.283);
    if (coherent && i % 64 != 0) { /* drift from the previous query */
      for (int a = 0; a < 3; a++)
        q[i][a] = q[i - 1][a] +
                  0.01f * (hi[a] - lo[a]) * (float)satf_rng_range(&rng, -1, 1);
      q[i][3] = q[i - 1][3] + 0.02f;
      q[i][4] = q[i - 1][4] + 0.01f;
    }
  }
  double sink = 0, t0 = satf_now_seconds();
  for (int i = 0; i < n; i++) {
    satf_db_lookup(db, q[i], q[i][3], q[i][4], k, re, al);
    sink += re[i & 15];
  }
  double dt = satf_now_seconds() - t0;
  free(q);
  if (sink == 12345.678)
    puts("");
  return n / dt;
}

int main(int argc, char **argv) {
  satf_build_params p = satf_build_params_default();
  p.samples = argc > 1 ? atoi(argv[1]) : 64;
  int cores = satf_cpu_count();
  double r1 = build_rate(&p, 1, NULL);
  satf_db *db = NULL;
  double rn = build_rate(&p, cores, &db);
  printf("build   %d samples x %dx%d x %d: 1 thread %.0f HRIRs/s, %d threads "
         "%.0f HRIRs/s, speed-up %.2fx\n",
         p.samples, p.n_view, p.n_light, p.trace.width, r1, cores, rn, rn / r1);
  for (int k = 1; k <= 4; k *= 4)
    printf("lookup  k=%d: %.2f M look-ups/s random, %.2f M/s coherent, on one "
           "core (%d-sample records)\n",
           k, lookup_rate(db, k, 2000000, 0) / 1e6,
           lookup_rate(db, k, 2000000, 1) / 1e6, p.trace.width);
  satf_db_destroy(db);
  return 0;
}
