/* measure_db_range.c - whether a database's sectors cover what the shells
 * of imported hair look up. A measuring program, not a test:
 * `measure_db_range DATABASE.exr SCENE.json...`.
 *
 * For every cluster the renderer draws as shells (not as its strands,
 * hierarchy_sparse at the default), the density features of its boundary
 * sectors (SATF sec. 5.2), computed as hierarchy.c computes them: one
 * look-up per sector per instance (maps_fiber.c looks up each boundary
 * sector once per light). Prints, per feature, the distribution of the
 * scene's values (min / p5 / median / p95 / max over the look-ups) beside
 * the database's range, the share of look-ups outside that range on each
 * feature and on any, and the strand width relative to the sector's size:
 * sigma (half the strand diameter) over the sector's depth (its radial
 * extent) and over its arc length at mid depth, against the database's
 * sectors' (satf_sector_ranges_default's sigma over the canonical shape).
 * Last, the look-up's nearest sample: its distance in the range-normalised
 * feature space (beside 0..0.1) and its rho_st less the sector's (beside
 * -0.05..0.05), the share beyond those. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "measure_samples.h"
#include "renderer_internal.h"
#include "satf/db.h"
#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/offline.h"
#include "satf/scene.h"

/* sectors holding at least this mean coverage: where a record shows (a
 * lone strand's tail reaching into a sector gives it centroids at its
 * edge, 0 or 1, and a record next to empty) */
#define SEEN_RHO 0.01

/* v, `times` times (once per instance) */
static void push_n(samples *s, float v, int times) {
  for (int i = 0; i < times; i++)
    push(s, v);
}

static void report(const char *name, samples *s, double lo, double hi) {
  if (s->n == 0) {
    printf("  %-14s (no shells)\n", name);
    return;
  }
  samples_sort(s);
  size_t out = 0;
  for (size_t i = 0; i < s->n; i++)
    out += s->v[i] < lo || s->v[i] > hi;
  printf("  %-14s %8.4f %8.4f %8.4f %8.4f %8.4f | db %8.4f .. %8.4f  "
         "outside %5.1f%%\n",
         name, s->v[0], s->v[s->n / 20], s->v[s->n / 2], s->v[(s->n * 19) / 20],
         s->v[s->n - 1], lo, hi, 100.0 * (double)out / (double)s->n);
  s->n = 0;
}

static int measure(const char *path, const satf_db *db, const float lo[3],
                   const float hi[3], const satf_build_params *bp) {
  satf_scene *scene = NULL;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  samples f[3] = {{0}}, depth = {0}, arc = {0}, near = {0}, drho = {0};
  long lookups = 0, outside = 0, seen = 0, seen_out = 0;
  int shells = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    const satf_scene_cluster *c = &mc->prototype;
    if (c->density.type == SATF_SCENE_DENSITY_VDB ||
        hierarchy_sparse(c, SATF_SPARSE_STRANDS_DEFAULT))
      continue;
    satf_cluster *cl = NULL;
    satf_strands *st = NULL;
    satf_shell_params sh = {c->shell.layers, c->shell.st, c->shell.su,
                            c->shell.core};
    size_t ns = (size_t)(sh.st + 1) * (size_t)sh.layers * (size_t)sh.su;
    float *feat = malloc(3 * ns * sizeof *feat);
    if (!feat || hierarchy_cluster_create(c, &cl, &err) != SATF_OK ||
        satf_strands_create(&c->density, &st, &err) != SATF_OK ||
        satf_sector_features(cl, &sh, st, NULL, NULL, 0, feat, &err) !=
            SATF_OK) {
      fprintf(stderr, "%s: macro_clusters[%d]: %s\n", path, m,
              feat ? err.message : "out of memory");
      return 1;
    }
    shells++;
    int times = mc->n_instances;
    for (size_t q = 0; q < ns; q++) {
      int any = 0;
      for (int a = 0; a < 3; a++) {
        push_n(&f[a], feat[3 * q + a], times);
        any |= feat[3 * q + a] < lo[a] || feat[3 * q + a] > hi[a];
      }
      lookups += times;
      outside += any ? times : 0;
      /* the nearest sample: how far in the look-up's range-normalised
       * space, and how much denser or sparser */
      int idx;
      float d2;
      if (satf_db_nearest(db, feat + 3 * q, 1, &idx, &d2) == 1) {
        push_n(&near, sqrtf(d2), times);
        push_n(&drho, satf_db_features(db, idx)[0] - feat[3 * q], times);
      }
      if (feat[3 * q] >= SEEN_RHO) {
        seen += times;
        seen_out += any ? times : 0;
      }
    }
    /* the strand's Gaussian sigma against the sector's size, both in
     * units of the cluster radius (v = 1 at the envelope) */
    float sigma = 0.5f * c->density.strand_width;
    float d = (1.0f - sh.core) / (float)sh.layers;
    for (int k = 0; k < sh.layers; k++) {
      float vm = sh.core + d * ((float)k + 0.5f);
      int n = times * (sh.st + 1) * sh.su;
      push_n(&depth, sigma / d, n);
      push_n(&arc, sigma / (vm * 6.2831853f / (float)sh.su), n);
    }
    free(feat);
    satf_strands_destroy(st);
    satf_cluster_destroy(cl);
  }
  printf("%s: %d clusters drawn as shells, %ld sector look-ups, %.1f%% "
         "outside the database's range on some feature\n",
         path, shells, lookups,
         lookups ? 100.0 * (double)outside / (double)lookups : 0.0);
  printf("  of those with rho_st >= %g (%.1f%% of them): %.1f%% outside\n",
         SEEN_RHO, lookups ? 100.0 * (double)seen / (double)lookups : 0.0,
         seen ? 100.0 * (double)seen_out / (double)seen : 0.0);
  printf("  %-14s %8s %8s %8s %8s %8s\n", "feature", "min", "p5", "median",
         "p95", "max");
  const char *names[3] = {"rho_st", "rho_s", "rho_t"};
  for (int a = 0; a < 3; a++)
    report(names[a], &f[a], lo[a], hi[a]);
  /* the sigma the build drew from (offline/sector.c) */
  satf_sector_ranges r = satf_sector_ranges_default(bp->kind);
  const satf_sector_shape *s = &bp->shape;
  double sd = s->r_outer - s->r_inner;
  double sa = 0.5 * (s->r_inner + s->r_outer) * s->phase_span;
  report("sigma/depth", &depth, r.sigma_lo / sd, r.sigma_hi / sd);
  report("sigma/arc", &arc, r.sigma_lo / sa, r.sigma_hi / sa);
  report("nearest dist", &near, 0.0, 0.1);
  report("nearest drho", &drho, -0.05, 0.05);
  for (int a = 0; a < 3; a++)
    free(f[a].v);
  free(depth.v);
  free(arc.v);
  free(near.v);
  free(drho.v);
  satf_scene_destroy(scene);
  return 0;
}

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: measure_db_range DATABASE.exr SCENE.json...\n");
    return 2;
  }
  satf_db *db = NULL;
  satf_error err;
  if (satf_db_read(argv[1], &db, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  float lo[3], hi[3];
  satf_db_feature_range(db, lo, hi);
  int rc = 0;
  for (int i = 2; i < argc && rc == 0; i++)
    rc = measure(argv[i], db, lo, hi, satf_db_params(db));
  satf_db_destroy(db);
  return rc;
}
