/* bench_lookup - the SATF look-up defaults measured (a benchmark, not a
 * test): k, the database samples blended per look-up (SATF eq. 4), and the
 * grid of nodes on which the renderer samples a sector's density for its
 * features (sec. 5.2; the database's own sectors use their build grid).
 *
 *   bench_lookup heldout DB [SECTORS]
 *     held-out error: sectors drawn like the database's (another seed),
 *     traced directly (eq. 5) and looked up at random azimuths, with
 *     features from the sector's strands sampled on G x G nodes, for k = 1,
 *     2, 4, 8 and G = 8, 16, 32: RMS of reflectance and alpha.
 *   bench_lookup maps DB SCENE [FRAMES]
 *     the maps of every cluster of a scene (procedural density) for the
 *     scene's camera and key light, for every (G, k): the seam measure of
 *     maps.h (mean jump across HSV boundaries / mean step inside an HSV)
 *     and the map stage's time per frame on one thread (FRAMES frames per
 *     setting, settings taken in turn so load on the machine hits all
 *     alike), plus the features' time per G.
 *   bench_lookup turn DB SCENE [FRAMES] [kk|physical]
 *     the renderer's per-frame CPU work (SATF Table 1: I azimuths, C
 *     look-ups, M upload; cluster_cpu.c) with the camera turning 2 degrees a
 * frame, so every HSV is looked up again: ms per frame on 1 and on 2 threads
 *     (taken in turn, frame by frame), and I + C + M per 100K HSVs;
 *     and the process's CPU time in those stages, which other
 *     load on the machine inflates less than their wall time (all threads,
 *     GL's included). physical: the physical shading mode (give a fibre
 *     DB).
 *     With DUMP, writes every instance's texels after the last frame
 *     there (raw floats), to compare the maps of two builds. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_turn.h"
#include "half.h"
#include "maps.h"
#include "mat4.h"
#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/density.h"
#include "satf/gl.h"
#include "satf/math.h"
#include "satf/offline.h"
#include "satf/render.h"
#include "satf/scene.h"

static const int KS[] = {1, 2, 4, 8};
static const int GS[] = {8, 16, 32};
enum { NK = 4, NG = 3 };

static void die(const char *what, const satf_error *err) {
  fprintf(stderr, "bench_lookup: %s: %s\n", what, err ? err->message : "");
  exit(1);
}

/* ---- held-out error ---------------------------------------------------- */

static int heldout(const satf_db *db, int sectors) {
  const satf_build_params *p = satf_db_params(db);
  int w = p->trace.width;
  uint64_t seed = p->seed + 0x5A7F; /* sectors the database never saw */
  double sre[NG][NK] = {{0}}, sal[NG][NK] = {{0}};
  long count = 0;
  float *r0 = malloc((size_t)w * 4 * sizeof(float)), *a0 = r0 + w,
        *r1 = r0 + 2 * w, *a1 = r0 + 3 * w;
  satf_rng rng;
  satf_rng_seed(&rng, 7, 7);
  satf_error err;
  for (int h = 0; h < sectors; h++) {
    satf_sector_recipe recipe;
    satf_sector_recipe_random(seed, (uint64_t)h, &recipe);
    satf_sector *truth = NULL;
    if (satf_build_sector(p, seed, (uint64_t)h, &truth, &err) != SATF_OK)
      die("sector", &err);
    float f[NG][3];
    for (int g = 0; g < NG; g++) {
      /* the same strands, sampled on G x G nodes as the renderer does */
      satf_sector *s = NULL;
      if (satf_sector_create(&p->shape, GS[g], GS[g], recipe.strand_sigma, &s,
                             &err) != SATF_OK)
        die("sector", &err);
      satf_sector_fill(s, &recipe, seed, (uint64_t)h);
      satf_density_features(s->density, s->ns, s->nt, f[g]);
      satf_sector_destroy(s);
    }
    for (int a = 0; a < 4; a++) {
      float tv = (float)satf_rng_range(&rng, 0, SATF_TWO_PI_F);
      float tl = (float)satf_rng_range(&rng, 0, SATF_TWO_PI_F);
      if (satf_trace_hrir(truth, &p->trace, tv, tl, r0, a0, &err) != SATF_OK)
        die("trace", &err);
      for (int g = 0; g < NG; g++)
        for (int k = 0; k < NK; k++) {
          satf_db_lookup(db, f[g], tv, tl, KS[k], r1, a1);
          for (int j = 0; j < w; j++) {
            sre[g][k] += (double)(r0[j] - r1[j]) * (r0[j] - r1[j]);
            sal[g][k] += (double)(a0[j] - a1[j]) * (a0[j] - a1[j]);
          }
        }
      count += w;
    }
    satf_sector_destroy(truth);
  }
  printf("held-out look-up error, %d sectors x 4 random azimuth pairs "
         "(database: %d samples, grid %d):\n",
         sectors, p->samples, p->grid);
  printf("  G   k   RMS(re,alpha)  RMS re   RMS alpha\n");
  for (int g = 0; g < NG; g++)
    for (int k = 0; k < NK; k++)
      printf("  %2d  %d   %.4f         %.4f   %.4f\n", GS[g], KS[k],
             sqrt((sre[g][k] + sal[g][k]) / (2.0 * count)),
             sqrt(sre[g][k] / count), sqrt(sal[g][k] / count));
  free(r0);
  return 0;
}

/* ---- maps: seams and time ---------------------------------------------- */

/* The density queries of satf_sector_features on grid x grid nodes, one
 * satf_strands_density call each (strand positions computed per query, as
 * the sampling did before it computed them once per t slice): its time. */
static double features_per_query_ms(const satf_cluster *cluster,
                                    const satf_shell_params *sh,
                                    const satf_strands *strands, int grid) {
  double t0 = satf_now_seconds(), sum = 0.0;
  for (int i = 0; i <= sh->st; i++) {
    float t = (float)i / (float)sh->st;
    for (int k = 0; k < sh->layers; k++) {
      float v0 = satf_shell_layer_v(sh, k), v1 = satf_shell_layer_v(sh, k + 1);
      for (int j = 0; j < sh->su; j++)
        for (int b = 0; b < grid; b++) {
          float u = SATF_TWO_PI_F * ((float)j + (float)b / (float)(grid - 1)) /
                    (float)sh->su;
          for (int a = 0; a < grid; a++) {
            float v = v0 + (v1 - v0) * (float)a / (float)(grid - 1);
            sum += satf_strands_density(strands, t, v * cosf(u), v * sinf(u));
          }
        }
    }
  }
  (void)cluster;
  if (sum < 0.0) /* keeps the loop */
    printf("%g\n", sum);
  return 1e3 * (satf_now_seconds() - t0);
}

typedef struct bproto {
  satf_cluster *cluster;
  satf_strands *strands;
  satf_shell_geom base[NG];     /* frames and features per grid */
  satf_shell_geom geom[NG][NK]; /* shallow copies with their neighbours */
  const satf_scene_macro_cluster *mc;
} bproto;

/* One frame of the map stage for setting (g, k): every instance's azimuths,
 * layers and s-maps; adds seams when `seams` is given. Returns look-ups. */
static long frame(const satf_scene *scene, const satf_maps *maps, bproto *bp,
                  int np, int g, int k, float *angles, float *tex,
                  satf_maps_seams *seams) {
  satf_map_options opt = satf_map_options_default();
  opt.k_nearest = KS[k];
  int w = satf_maps_width(maps);
  long lookups = 0;
  for (int q = 0; q < np; q++) {
    const satf_shell_geom *geom = &bp[q].geom[g][k];
    size_t n = satf_maps_layer_texels(geom, w) * 4;
    for (int i = 0; i < bp[q].mc->n_instances; i++) {
      float inv[16], eye[3], light[4];
      if (!satf_mat4_invert(bp[q].mc->instances[i].m, inv))
        continue;
      satf_mat4_point(inv, scene->camera.position, eye);
      const satf_scene_light *l = &scene->lights[0];
      if (l->type == SATF_SCENE_LIGHT_POINT) {
        satf_mat4_point(inv, l->position, light);
        light[3] = 1.0f;
      } else {
        float d[3] = {-l->direction[0], -l->direction[1], -l->direction[2]};
        satf_mat4_vector(inv, d, light);
        light[3] = 0.0f;
      }
      satf_maps_angles(geom, eye, light, angles);
      for (int layer = 0; layer < geom->shell.layers; layer++) {
        lookups += satf_maps_build_layer(maps, geom, angles, &opt, layer,
                                         tex + (size_t)layer * n);
        if (seams)
          satf_maps_seams_add(geom, w, tex + (size_t)layer * n, seams);
      }
      satf_maps_shadow_sums(geom, w, tex);
    }
  }
  return lookups;
}

static int maps_bench(const satf_db *db, const char *path, int frames) {
  satf_scene *scene = NULL;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK)
    die(path, &err);
  satf_maps *maps = NULL;
  if (satf_maps_create(db, &maps, &err) != SATF_OK)
    die("maps", &err);
  int w = satf_maps_width(maps);
  bproto *bp = calloc((size_t)scene->n_macro_clusters, sizeof *bp);
  int np = 0;
  size_t max_sectors = 0, max_texels = 0;
  double feat_ms[NG] = {0}, query_ms = 0.0;
  long hsvs = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_cluster *c = &scene->macro_clusters[m].prototype;
    if (c->density.type != SATF_SCENE_DENSITY_PROCEDURAL) {
      fprintf(stderr,
              "bench_lookup: %s: macro cluster %d: VDB density "
              "skipped\n",
              path, m);
      continue;
    }
    bproto *b = &bp[np++];
    b->mc = &scene->macro_clusters[m];
    if (hierarchy_cluster_create(c, &b->cluster, &err) != SATF_OK)
      die("cluster", &err);
    if (satf_strands_create(&c->density, &b->strands, &err) != SATF_OK)
      die("strands", &err);
    satf_shell_params sh = {c->shell.layers, c->shell.st, c->shell.su,
                            c->shell.core};
    for (int g = 0; g < NG; g++) {
      if (satf_shell_geom_create(b->cluster, &sh, &b->base[g], &err) != SATF_OK)
        die("shell", &err);
      double t0 = satf_now_seconds();
      if (satf_sector_features_grid(b->cluster, &sh, b->strands, NULL, NULL,
                                    GS[g], 1, b->base[g].features,
                                    &err) != SATF_OK)
        die("features", &err);
      feat_ms[g] += 1e3 * (satf_now_seconds() - t0);
      if (GS[g] == 8)
        query_ms += features_per_query_ms(b->cluster, &sh, b->strands, 8);
      for (int k = 0; k < NK; k++) {
        satf_map_options opt = satf_map_options_default();
        opt.k_nearest = KS[k];
        b->geom[g][k] = b->base[g];
        b->geom[g][k].neighbors = NULL;
        if (satf_maps_prepare(maps, &b->geom[g][k], &opt, &err) != SATF_OK)
          die("neighbours", &err);
      }
    }
    size_t ns = satf_shell_sector_count(&sh);
    size_t nt = satf_maps_layer_texels(&b->base[0], w) * (size_t)sh.layers;
    max_sectors = ns > max_sectors ? ns : max_sectors;
    max_texels = nt > max_texels ? nt : max_texels;
    hsvs += (long)satf_shell_hsv_count(&sh) * b->mc->n_instances;
  }
  float *angles = malloc(2 * max_sectors * sizeof(float));
  float *tex = calloc(max_texels * 4, sizeof(float));
  satf_maps_seams seams[NG][NK];
  long lookups[NG][NK];
  memset(seams, 0, sizeof seams);
  for (int g = 0; g < NG; g++)
    for (int k = 0; k < NK; k++)
      lookups[g][k] =
          frame(scene, maps, bp, np, g, k, angles, tex, &seams[g][k]);
  double ms[NG][NK] = {{0}};
  for (int f = 0; f < frames; f++) /* settings in turn */
    for (int g = 0; g < NG; g++)
      for (int k = 0; k < NK; k++) {
        double t0 = satf_now_seconds();
        frame(scene, maps, bp, np, g, k, angles, tex, NULL);
        ms[g][k] += 1e3 * (satf_now_seconds() - t0) / frames;
      }
  printf("%s: %ld HSVs, database width %d; seams = mean |jump| across HSV "
         "boundaries / mean |step| inside an HSV (phase direction); t-jump = "
         "mean |difference| of neighbouring HSVs at their shared t\n",
         path, hsvs, w);
  printf("  G   k   seam re  seam alpha  jump alpha  step alpha  t-jump "
         "alpha  t-jump re  HSV-to-HSV alpha  HSV-to-HSV re  look-ups  map "
         "ms/frame (1 thread)  ms vs k=1\n");
  for (int g = 0; g < NG; g++)
    for (int k = 0; k < NK; k++) {
      const satf_maps_seams *s = &seams[g][k];
      double rre, ral;
      satf_maps_seams_ratio(s, &rre, &ral);
      printf("  %2d  %d   %.3f    %.3f       %.4f      %.4f      %.4f"
             "        %.4f     %.4f            %.4f         %8ld  %.2f         "
             "            %.2f\n",
             GS[g], KS[k], rre, ral, s->al_edge / (double)s->n_al_edge,
             s->al_inner / (double)s->n_al_inner,
             s->al_t / (double)(s->n_al_t ? s->n_al_t : 1),
             s->re_t / (double)(s->n_re_t ? s->n_re_t : 1),
             s->al_hsv / (double)s->n_al_hsv,
             s->re_hsv / (double)(s->n_re_hsv ? s->n_re_hsv : 1), lookups[g][k],
             ms[g][k], ms[g][k] / ms[g][0]);
    }
  for (int g = 0; g < NG; g++)
    printf("  features on %dx%d nodes: %.1f ms (1 thread, once per "
           "prototype)\n",
           GS[g], GS[g], feat_ms[g]);
  printf("  8x8 nodes, strand positions per query (the sampling before "
         "positions per t slice): %.1f ms\n",
         query_ms);
  for (int q = 0; q < np; q++) {
    for (int g = 0; g < NG; g++) {
      for (int k = 0; k < NK; k++)
        satf_neighbor_cache_free(bp[q].geom[g][k].neighbors);
      satf_shell_geom_destroy(&bp[q].base[g]);
    }
    satf_strands_destroy(bp[q].strands);
    satf_cluster_destroy(bp[q].cluster);
  }
  free(bp);
  free(angles);
  free(tex);
  satf_maps_destroy(maps);
  satf_scene_destroy(scene);
  return 0;
}

/* ---- turn: the renderer's I + C + M with a turning camera -------------- */

/* CPU time of the whole process, every thread, in ms. */
static double cpu_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

/* Every instance's texels, raw floats (unpacked from the renderer's
 * halfs), to `path`. */
static void dump_texels(const satf_renderer *r, const char *path) {
  FILE *f = fopen(path, "wb");
  if (!f)
    die(path, NULL);
  for (int i = 0; i < r->ninsts; i++) {
    const satf_shell_geom *g = &r->insts[i].geom;
    size_t n = satf_maps_layer_texels(g, r->w) * 4 * (size_t)g->shell.layers *
               (size_t)r->quads;
    float *v = malloc(n * sizeof *v);
    if (!v)
      die("out of memory", NULL);
    half_unpack(r->insts[i].texels, v, n);
    if (fwrite(v, sizeof(float), n, f) != n)
      die(path, NULL);
    free(v);
  }
  if (fclose(f) != 0)
    die(path, NULL);
}

static int turn_bench(const satf_db *db, const char *path, int frames,
                      int physical, const char *dump) {
  satf_scene *scene = NULL;
  satf_gl_context *ctx = NULL;
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK)
    die(path, &err);
  if (physical)
    scene->material.model = SATF_MATERIAL_PHYSICAL;
  if (satf_gl_context_create_headless(64, 64, &ctx, &err) != SATF_OK)
    die("GL", &err);
  if (satf_renderer_create(scene, db, 64, 64, 2, &r, &err) != SATF_OK)
    die("renderer", &err);
  /* the CPU's look-ups are what this times */
  if (satf_renderer_set_maps(r, SATF_MAPS_CPU, &err) != SATF_OK)
    die("maps", &err);
  satf_frame_timing t;
  if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
    die("render", &err);
  enum { NT = 2 };
  /* per thread count: sums and minima over frames of I, C, M, I + C + M
   * and the CPU time; the minimum is what load on the machine spared */
  double sum[NT][5] = {{0}}, lo[NT][5];
  for (int th = 0; th < NT; th++)
    for (int v = 0; v < 5; v++)
      lo[th][v] = INFINITY;
  long lookups = 0;
  float step = 2.0f * SATF_PI_F / 180.0f;
  for (int f = 0; f < frames; f++)
    for (int th = 0; th < NT; th++) { /* thread counts in turn */
      r->threads = th + 1;
      bench_turn(satf_renderer_camera(r), step);
      double c0 = cpu_ms();
      if (cluster_cpu_update_maps(r, &t, &err) != SATF_OK)
        die("maps", &err);
      double v[5] = {t.index_ms, t.maps_ms, t.upload_ms,
                     t.index_ms + t.maps_ms + t.upload_ms, cpu_ms() - c0};
      for (int k = 0; k < 5; k++) {
        sum[th][k] += v[k] / frames;
        lo[th][k] = v[k] < lo[th][k] ? v[k] : lo[th][k];
      }
      lookups = t.lookups;
    }
  double hsvs = (double)r->stats.hsvs, per = 1e5 / (hsvs > 0 ? hsvs : 1);
  printf("%s (%s): %ld clusters, %.0f HSVs, %ld look-ups a frame, camera "
         "turning 2 degrees a frame, %d frames; ms per frame, mean / "
         "minimum\n",
         path, physical ? "physical" : "kk", r->stats.clusters, hsvs, lookups,
         frames);
  printf("  threads  I            C            M            I+C+M        "
         "I+C+M per 100K HSVs  CPU (all threads)\n");
  for (int th = 0; th < NT; th++) {
    printf("  %7d", th + 1);
    for (int k = 0; k < 4; k++)
      printf("  %5.2f/%5.2f", sum[th][k], lo[th][k]);
    printf("  %5.2f/%5.2f          %5.2f/%5.2f\n", sum[th][3] * per,
           lo[th][3] * per, sum[th][4], lo[th][4]);
  }
  if (dump)
    dump_texels(r, dump);
  satf_renderer_destroy(r);
  satf_gl_context_destroy(ctx);
  satf_scene_destroy(scene);
  return 0;
}

int main(int argc, char **argv) {
  if (argc < 3 || !strcmp(argv[1], "--help") ||
      (strcmp(argv[1], "heldout") && strcmp(argv[1], "maps") &&
       strcmp(argv[1], "turn")) ||
      (strcmp(argv[1], "heldout") && argc < 4)) {
    fprintf(argc < 2 || strcmp(argv[1], "--help") ? stderr : stdout,
            "usage: bench_lookup heldout DB [SECTORS]\n"
            "       bench_lookup maps DB SCENE [FRAMES]\n"
            "       bench_lookup turn DB SCENE [FRAMES] [kk|physical] [DUMP]\n"
            "Measures the look-up defaults: held-out error and HSV seams "
            "for k = 1, 2, 4, 8 blended samples and feature grids of 8, 16, "
            "32 nodes, and the map stage's time; the renderer's I + C + M "
            "with a turning camera.\n");
    return argc >= 2 && !strcmp(argv[1], "--help") ? 0 : 2;
  }
  satf_db *db = NULL;
  satf_error err;
  if (satf_db_read(argv[2], &db, &err) != SATF_OK)
    die(argv[2], &err);
  int rc;
  if (!strcmp(argv[1], "heldout"))
    rc = heldout(db, argc > 3 ? atoi(argv[3]) : 200);
  else if (!strcmp(argv[1], "maps"))
    rc = maps_bench(db, argv[3], argc > 4 ? atoi(argv[4]) : 5);
  else
    rc = turn_bench(db, argv[3], argc > 4 ? atoi(argv[4]) : 20,
                    argc > 5 && !strcmp(argv[5], "physical"),
                    argc > 6 ? argv[6] : NULL);
  satf_db_destroy(db);
  return rc;
}
