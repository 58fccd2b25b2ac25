/* bench_dom - the deep opacity map's cost and its shortcuts' image error
 * (a benchmark, not a test):
 *
 *   bench_dom DB SCENE [OUTDIR|-] [FRAMES] [--cost]
 *
 * 1. Reuse while only the eye moved: the maps' alpha, which the map sums,
 *    follows the eye's azimuth. For turns of 5 to 180 degrees: the map
 *    drawn with the camera turned, then kept for a frame at the scene's
 *    camera, against that frame with a map drawn for it (satf-compare's
 *    SSIM and luminance ratio; the coverage does not depend on shadows).
 *    The error of dropping the cluster shadows altogether is the scale.
 * 2. The map's cost (wall and process CPU time: llvmpipe's threads are
 *    the process's): FRAMES calls of cluster_dom_update drawing the map, in
 * turn with calls that keep it.
 * --cost: only 2. With OUTDIR the frames are written there as EXRs
 * (fresh.exr, noshadow.exr, keep_DEG.exr).
 *
 *   bench_dom DB SCENE [OUTDIR|-] [FRAMES] --anim TOL
 *
 * 3. Moving hair: every frame of the scene's animation, FRAMES times over,
 *    with the map kept while no cluster moved more than TOL texels or
 *    slabs (r->dom.move_tol), against a renderer drawing it every frame
 *    (the exact rule): S of each (wall ms, and the whole frame), whether
 *    the map was kept, how far the hair had moved, and the frame's error
 *    against the exact one (SSIM, mean |luminance change| as a share of
 *    what the cluster shadows change in that frame). With OUTDIR the
 *    first round's frames are written (anim_exact_NN.exr,
 *    anim_kept_NN.exr). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_setup.h"
#include "bench_turn.h"
#include "metrics.h"
#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/db.h"
#include "satf/gl.h"
#include "satf/math.h"
#include "satf/render.h"
#include "satf/scene.h"

static void die(const char *what, const satf_error *err) {
  bench_fail("bench_dom", what, err);
}

/* CPU seconds of the whole process: llvmpipe's threads too, and less
 * swayed than wall time by other processes on a shared machine. */
static double cpu_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static satf_image *frame(satf_renderer *r) {
  satf_image *img = NULL;
  satf_error err;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    die("render", &err);
  return img;
}

static compare_image compare_view(const satf_image *img, const char *name) {
  compare_image c = {
      name, satf_image_width(img), satf_image_height(img), NULL, NULL, NULL,
      NULL};
  const char *ch[4] = {"R", "G", "B", "A"};
  const float **dst[4] = {&c.r, &c.g, &c.b, &c.a};
  for (int k = 0; k < 4; k++)
    *dst[k] = satf_image_const_plane(img, satf_image_channel_index(img, ch[k]));
  return c;
}

/* Mean |luminance difference| over pixels either covers. */
static double lum_diff(const satf_image *a, const satf_image *b) {
  compare_image x = compare_view(a, "a"), y = compare_view(b, "b");
  double sum = 0.0;
  long n = 0;
  for (int i = 0; i < x.width * x.height; i++) {
    if (x.a[i] <= COMPARE_COVERED && y.a[i] <= COMPARE_COVERED)
      continue;
    sum += fabs(compare_luminance(x.r[i], x.g[i], x.b[i]) -
                compare_luminance(y.r[i], y.g[i], y.b[i]));
    n++;
  }
  return n ? sum / (double)n : 0.0;
}

static void report(const char *what, const satf_image *ref,
                   const satf_image *test, double scale) {
  compare_image a = compare_view(ref, "ref"), b = compare_view(test, "test");
  compare_result res;
  satf_error err;
  if (compare_measure(&a, &b, &res, &err) != SATF_OK)
    die("compare", &err);
  double d = lum_diff(ref, test);
  printf("%-22s IoU %.4f SSIM %.4f lum %.4f  |dlum| %.5f (%.1f%% of no "
         "shadows')\n",
         what, res.iou, res.ssim, res.lum_ratio, d,
         scale > 0 ? 100.0 * d / scale : 0.0);
}

static void save(const satf_image *img, const char *dir, const char *name) {
  if (!dir)
    return;
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  satf_error err;
  if (satf_image_write_exr(img, path, &err) != SATF_OK)
    die(path, &err);
}

/* 3.: the scene's animation, the map kept within tol, against the exact
 * rule. */
static void animation(const bench_setup *b, const char *dir, int rounds,
                      float tol) {
  int first = 0, last = 0;
  if (!satf_scene_frame_range(b->scene, &first, &last))
    die("--anim: the scene has no animation", NULL);
  satf_renderer *exact = b->r, *cheap = NULL;
  satf_error err;
  satf_scene *now = NULL, *before = NULL;
  int w = 0, h = 0;
  satf_renderer_size(exact, &w, &h);
  if (satf_scene_at_frame(b->scene, first, &now, &err) != SATF_OK ||
      satf_renderer_create(now, b->db, w, h, 0, &cheap, &err) != SATF_OK)
    die("--anim", &err);
  exact->dom.move_tol = -1.0f;
  cheap->dom.move_tol = tol;
  double s_sum[2] = {0}, total[2] = {0}, worst_ssim = 1.0, worst_share = 0.0,
         share_sum = 0.0;
  long kept = 0, n = 0;
  for (int round = 0; round < rounds; round++)
    for (int f = first; f <= last; f++) {
      satf_scene_destroy(before);
      before = now;
      now = NULL;
      if (satf_scene_at_frame(b->scene, f, &now, &err) != SATF_OK ||
          satf_renderer_set_scene(exact, now, NULL, &err) != SATF_OK ||
          satf_renderer_set_scene(cheap, now, NULL, &err) != SATF_OK)
        die("--anim frame", &err);
      satf_frame_timing t[2];
      satf_image *img[2] = {NULL, NULL};
      satf_renderer *rs[2] = {exact, cheap};
      long reuses = cheap->dom.reuses;
      float move = cluster_dom_hair_move(cheap);
      for (int k = 0; k < 2; k++)
        if (satf_renderer_render_image(rs[k], 0, &img[k], &t[k], &err) !=
            SATF_OK)
          die("--anim render", &err);
      int keep = cheap->dom.reuses > reuses;
      exact->effects.cluster_shadows = 0;
      satf_image *none = frame(exact);
      exact->effects.cluster_shadows = 1;
      double scale = lum_diff(img[0], none), d = lum_diff(img[0], img[1]);
      compare_image x = compare_view(img[0], "exact"),
                    y = compare_view(img[1], "cheap");
      compare_result res;
      if (compare_measure(&x, &y, &res, &err) != SATF_OK)
        die("compare", &err);
      double share = scale > 0 ? 100.0 * d / scale : 0.0;
      printf("frame %2d  S exact %6.2f kept %6.2f ms, frame %6.1f %6.1f ms"
             "  move %5.2f %s  SSIM %.5f  |dlum| %.5f (%.2f%% of the "
             "shadows')\n",
             f, t[0].shadow_ms, t[1].shadow_ms, t[0].total_ms, t[1].total_ms,
             move, keep ? "kept " : "drawn", res.ssim, d, share);
      if (round == 0) {
        char name[64];
        snprintf(name, sizeof name, "anim_exact_%02d.exr", f);
        save(img[0], dir, name);
        snprintf(name, sizeof name, "anim_kept_%02d.exr", f);
        save(img[1], dir, name);
      }
      s_sum[0] += t[0].shadow_ms;
      s_sum[1] += t[1].shadow_ms;
      total[0] += t[0].total_ms;
      total[1] += t[1].total_ms;
      kept += keep;
      n++;
      worst_ssim = res.ssim < worst_ssim ? res.ssim : worst_ssim;
      worst_share = share > worst_share ? share : worst_share;
      share_sum += share;
      for (int k = 0; k < 2; k++)
        satf_image_destroy(img[k]);
      satf_image_destroy(none);
    }
  printf("anim: %ld frames, tolerance %.2f: S exact %.2f ms, kept "
         "%.2f ms (%.3f of it), frame %.1f, %.1f ms (%.3f), kept %ld; SSIM >= "
         "%.5f, |dlum| %.2f%% of the shadows' on average, %.2f%% at most\n",
         n, tol, s_sum[0] / n, s_sum[1] / n, s_sum[1] / s_sum[0], total[0] / n,
         total[1] / n, total[1] / total[0], kept, worst_ssim, share_sum / n,
         worst_share);
  satf_renderer_destroy(cheap);
  satf_renderer_set_scene(exact, b->scene, NULL, &err);
  satf_scene_destroy(before);
  satf_scene_destroy(now);
}

int main(int argc, char **argv) {
  if (argc < 3 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
    fprintf(stderr,
            "usage: bench_dom DB SCENE [OUTDIR|-] [FRAMES] [--cost]\n"
            "       bench_dom DB SCENE [OUTDIR|-] [FRAMES] --anim TOL\n");
    return argc < 3 ? 2 : 0;
  }
  const char *dir = argc > 3 && strcmp(argv[3], "-") ? argv[3] : NULL;
  int frames = argc > 4 ? atoi(argv[4]) : 10;
  int cost_only = argc > 5 && !strcmp(argv[5], "--cost");
  int anim = argc > 6 && !strcmp(argv[5], "--anim");
  if (frames < 1)
    frames = 1;
  bench_setup b = bench_open("bench_dom", argv[1], argv[2], 0, 0);
  satf_renderer *r = b.r;
  if (anim) {
    animation(&b, dir, frames, (float)atof(argv[6]));
    bench_close(&b);
    return 0;
  }
  satf_scene_camera start = *satf_renderer_camera(r);
  r->dom.move_tol = -1.0f; /* the reference: the exact rule */
  r->effects.cluster_shadows = 1;
  satf_image *fresh = frame(r);
  save(fresh, dir, "fresh.exr");
  r->effects.cluster_shadows = 0;
  satf_image *none = frame(r);
  save(none, dir, "noshadow.exr");
  r->effects.cluster_shadows = 1;
  double scale = lum_diff(fresh, none);
  report("no cluster shadows", fresh, none, scale);
  satf_image_destroy(none);
  if (cost_only)
    goto timing;
  static const float turns[] = {5, 15, 30, 60, 90, 180};
  for (size_t k = 0; k < sizeof turns / sizeof turns[0]; k++) {
    r->dom.eye_tol = 0.0f; /* drawn at the turned eye */
    bench_turn(satf_renderer_camera(r), turns[k] * SATF_PI_F / 180.0f);
    satf_image_destroy(frame(r));
    *satf_renderer_camera(r) = start;
    r->dom.eye_tol = 4.0f; /* kept, whatever the turn */
    long before = r->dom.reuses;
    satf_image *kept = frame(r);
    if (r->dom.reuses != before + 1)
      die("the map was not kept", NULL);
    char name[64];
    snprintf(name, sizeof name, "keep_%.0f.exr", turns[k]);
    save(kept, dir, name);
    snprintf(name, sizeof name, "kept from %.0f deg", turns[k]);
    report(name, fresh, kept, scale);
    satf_image_destroy(kept);
  }
timing:
  /* 2. the map's cost, drawn and kept, frame by frame in turn */
  r->dom.eye_tol = 0.0f;
  double wall[2] = {0}, cpu[2] = {0};
  for (int f = 0; f <= frames; f++)
    for (int v = 0; v < 2; v++) {
      r->dom.valid = v == 1;
      glFinish();
      double w0 = satf_now_seconds(), c0 = cpu_seconds();
      cluster_dom_update(r);
      glFinish();
      if (f > 0) { /* the first round warms up */
        wall[v] += 1e3 * (satf_now_seconds() - w0);
        cpu[v] += 1e3 * (cpu_seconds() - c0);
      }
    }
  static const char *const ways[2] = {"drawn", "kept"};
  for (int v = 0; v < 2; v++)
    printf("S %-6s wall %7.2f ms, CPU %7.2f ms (%d frames)\n", ways[v],
           wall[v] / frames, cpu[v] / frames, frames);
  satf_image_destroy(fresh);
  bench_close(&b);
  return 0;
}
