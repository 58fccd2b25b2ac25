/* bench_shading - the physical shading mode's frame rate against kk's
 * under the same load (a benchmark, not a test):
 *
 *   bench_shading [--strands] KK_DB FIBER_DB FRAMES SCENE...
 *
 * --strands: both renderers draw each scene's source strands (its
 * "strands" key, at the file's thickness or the clusters' assumed width,
 * as satf-render --strands) instead of its clusters.
 *
 * For each scene, two renderers in one GL context, one shading kk from the
 * Phong database and one physical from the fibre database, walk the frames
 * of `satf-render --bench` (the animation, or the camera orbiting once;
 * satf_frontend_walk) in turn, frame by frame: each frame of one mode is
 * followed by the same frame of the other, so load on the machine hits
 * both alike. Prints per scene the mean ms per frame of each, their stage
 * times (Table 1's C and L, where the modes differ), the frame-rate ratio
 * physical / kk of the means, and the median of the per-frame ratios,
 * which a burst of other load moves least. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frontend.h"
#include "satf/common.h"
#include "satf/db.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "satf/scene.h"

enum { KK, PHYS, NMODES };
static const char *const PROG = "bench_shading";

static void die(const char *what, const satf_error *err) {
  fprintf(stderr, "%s: %s: %s\n", PROG, what, err ? err->message : "");
  exit(1);
}

static int by_value(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* One scene's row. */
static void bench_scene(const char *path, satf_db *const db[NMODES],
                        long frames, int strands) {
  satf_error err;
  satf_scene *scene[NMODES];
  satf_renderer *r[NMODES];
  int w = 0, h = 0;
  for (int m = 0; m < NMODES; m++) {
    if (satf_scene_load(path, &scene[m], &err) != SATF_OK)
      die(path, &err);
    scene[m]->material.model =
        m == KK ? SATF_MATERIAL_KK : SATF_MATERIAL_PHYSICAL;
    w = scene[m]->image.width > 0 ? scene[m]->image.width : 640;
    h = scene[m]->image.height > 0 ? scene[m]->image.height : 480;
    if (satf_renderer_create(scene[m], db[m], w, h, 0, &r[m], &err) != SATF_OK)
      die(path, &err);
    if (strands) { /* as satf-render --strands */
      satf_frontend fe = {.scene = scene[m]};
      if (satf_frontend_load_strands(PROG, &fe) != SATF_OK)
        exit(1);
      satf_status st = satf_frontend_apply_strands(r[m], &fe, &err);
      satf_strand_set_destroy(fe.strands);
      if (st != SATF_OK)
        die(path, &err);
    }
  }
  satf_frontend_walk walk[NMODES];
  satf_frame_timing t, sum[NMODES];
  double ms[NMODES] = {0, 0};
  double *ratio = malloc((size_t)frames * sizeof *ratio);
  if (!ratio)
    die(path, NULL);
  memset(sum, 0, sizeof sum);
  for (int m = 0; m < NMODES; m++) { /* a warm-up frame each */
    if (satf_renderer_render(r[m], SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
      die(path, &err);
    satf_frontend_walk_begin(&walk[m], r[m], scene[m], frames);
  }
  for (long f = 0; f < frames; f++) {
    double frame_ms[NMODES];
    /* which mode goes first alternates: neither always follows the other */
    for (int i = 0; i < NMODES; i++) {
      int m = (int)((i + f) % NMODES);
      double t0 = satf_now_seconds();
      if (satf_frontend_walk_step(&walk[m], f, &err) != SATF_OK ||
          satf_renderer_render(r[m], SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
        die(path, &err);
      frame_ms[m] = 1e3 * (satf_now_seconds() - t0);
      ms[m] += frame_ms[m];
      sum[m].maps_ms += t.maps_ms;
      sum[m].lighting_ms += t.lighting_ms;
      sum[m].shadow_ms += t.shadow_ms;
    }
    ratio[f] = frame_ms[KK] / frame_ms[PHYS]; /* FPS physical / kk */
  }
  qsort(ratio, (size_t)frames, sizeof *ratio, by_value);
  double n = (double)frames;
  printf("%-18s %8.1f %8.1f %6.1f %6.1f %6.1f %6.1f %7.3f %7.3f\n",
         scene[KK]->name ? scene[KK]->name : path, ms[KK] / n, ms[PHYS] / n,
         sum[KK].maps_ms / n, sum[PHYS].maps_ms / n, sum[KK].lighting_ms / n,
         sum[PHYS].lighting_ms / n, ms[KK] / ms[PHYS], ratio[frames / 2]);
  fflush(stdout);
  free(ratio);
  for (int m = 0; m < NMODES; m++) {
    satf_frontend_walk_end(&walk[m], 1);
    satf_renderer_destroy(r[m]);
    satf_scene_destroy(scene[m]);
  }
}

int main(int argc, char **argv) {
  int strands = argc > 1 && !strcmp(argv[1], "--strands");
  if (strands) { /* the rest as without it */
    argv[1] = argv[0];
    argv++;
    argc--;
  }
  if (argc < 5 || !strcmp(argv[1], "--help")) {
    fprintf(argc < 5 ? stderr : stdout,
            "usage: %s [--strands] KK_DB FIBER_DB FRAMES SCENE...\n"
            "Times kk and physical shading frame by frame in turn over the\n"
            "frames of satf-render --bench; prints ms per frame, C and L of\n"
            "each, and the frame-rate ratio physical / kk (of the means and\n"
            "the median per frame). --strands: both draw the scenes'\n"
            "source strands instead of their clusters.\n",
            PROG);
    return argc < 5;
  }
  long frames = strtol(argv[3], NULL, 10);
  if (frames < 1 || frames > 100000) {
    fprintf(stderr, "%s: FRAMES: expected 1 to 100000, got '%s'\n", PROG,
            argv[3]);
    return 1;
  }
  satf_error err;
  satf_db *db[NMODES];
  for (int m = 0; m < NMODES; m++)
    if (satf_db_read(argv[1 + m], &db[m], &err) != SATF_OK)
      die(argv[1 + m], &err);
  if (satf_db_kind(db[PHYS]) != SATF_RECORD_FIBER) {
    fprintf(stderr, "%s: %s: not a fibre database (satf-build --kind fiber)\n",
            PROG, argv[2]);
    return 1;
  }
  satf_gl_context *ctx;
  if (satf_gl_context_create_headless(640, 480, &ctx, &err) != SATF_OK)
    die("GL", &err);
  printf("%-18s %8s %8s %6s %6s %6s %6s %7s %7s\n", "scene", "kk ms", "phys ms",
         "C kk", "C phys", "L kk", "L phys", "ratio", "median");
  for (int a = 4; a < argc; a++)
    bench_scene(argv[a], db, frames, strands);
  satf_gl_context_destroy(ctx);
  for (int m = 0; m < NMODES; m++)
    satf_db_destroy(db[m]);
  return 0;
}
