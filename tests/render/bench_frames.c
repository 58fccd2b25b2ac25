/* bench_frames - where a frame's time goes (a benchmark, not a
 * test):
 *
 *   bench_frames DB SCENE [FRAMES] [WIDTHxHEIGHT]
 *
 * renders the scene at its camera and prints, per stage (SATF Table 1: I,
 * C, M, S, L), the mean of FRAMES frames in four situations: the camera
 * turning 2 degrees a frame (every view azimuth changes), the same with
 * one draw per instance instead of one per run of a macro-cluster's
 * instances, a still frame (nothing changed: incremental look-ups make no
 * look-up and the deep opacity map is kept) and a still frame looking
 * every HSV up again (the old way). Then, of the still frame's exact
 * composite: fragments stored, pixels covered, fragments per covered pixel
 * and the share of fragments whose ray saturated (transmittance below
 * 1/512: shade_fs.glsl's early ray termination stopped it), read back from
 * the per-pixel arrays; and the draw calls of the shading pass both ways.
 * Situations are taken in turn, frame by frame, so load on the machine
 * hits all alike. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_setup.h"
#include "bench_turn.h"
#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/db.h"
#include "satf/gl.h"
#include "satf/math.h"
#include "satf/render.h"
#include "satf/scene.h"

enum { ORBIT, ORBIT_PER_INSTANCE, STILL, STILL_FULL, NSIT };
static const char *const NAMES[NSIT] = {"camera turning", "  one draw/inst",
                                        "still", "  full look-ups"};

static void die(const char *what, const satf_error *err) {
  fprintf(stderr, "bench_frames: %s: %s\n", what, err ? err->message : "");
  exit(1);
}

static void add(satf_frame_timing *sum, const satf_frame_timing *t) {
  sum->index_ms += t->index_ms;
  sum->maps_ms += t->maps_ms;
  sum->upload_ms += t->upload_ms;
  sum->shadow_ms += t->shadow_ms;
  sum->lighting_ms += t->lighting_ms;
  sum->total_ms += t->total_ms;
  sum->lookups += t->lookups;
}

/* Draw calls of the shading pass: runs of one prototype's instances in one
 * texture array and of one winding (passes.c, draw_clusters). */
static int draw_calls(const satf_renderer *r, int instanced) {
  int calls = 0;
  for (int i = 0; i < r->ninsts; i++)
    calls += !instanced || i == 0 ||
             r->insts[i].proto != r->insts[i - 1].proto ||
             r->insts[i].tex != r->insts[i - 1].tex ||
             r->insts[i].mirrored != r->insts[i - 1].mirrored;
  return calls;
}

/* An IEEE half's value (GLSL packHalf2x16). */
static float half_value(unsigned h) {
  int e = (int)(h >> 10) & 31, m = (int)(h & 1023);
  float v = e == 0    ? ldexpf((float)m, -24)
            : e == 31 ? INFINITY
                      : ldexpf((float)(m | 1024), e - 25);
  return h & 0x8000u ? -v : v;
}

/* The still frame's fragment arrays: fragments, covered pixels and those
 * fragments whose alpha is at least 1 - 1/512. */
static void fragment_stats(const satf_renderer *r, long *frags, long *pixels,
                           long *saturated) {
  size_t n = (size_t)r->view.width * (size_t)r->view.height;
  GLuint *counts = malloc(n * sizeof(GLuint));
  GLuint *frags_px = malloc(n * (size_t)r->lists.slots * 4 * sizeof(GLuint));
  *frags = *pixels = *saturated = 0;
  if (!counts || !frags_px) {
    free(counts);
    free(frags_px);
    return;
  }
  glBindTexture(GL_TEXTURE_2D, r->lists.counts);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, counts);
  glBindTexture(GL_TEXTURE_2D_ARRAY, r->lists.frags);
  glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                frags_px);
  for (size_t p = 0; p < n; p++) {
    GLuint c =
        counts[p] < (GLuint)r->lists.slots ? counts[p] : (GLuint)r->lists.slots;
    *frags += c;
    *pixels += c > 0;
    for (GLuint s = 0; s < c; s++) {
      /* slot s of pixel p: .g packs (blue, alpha) as halves (shade_fs) */
      GLuint g = frags_px[4 * ((size_t)s * n + p) + 1];
      float alpha = half_value(g >> 16);
      *saturated += alpha >= 1.0f - 1.0f / 512.0f;
    }
  }
  free(counts);
  free(frags_px);
}

int main(int argc, char **argv) {
  if (argc < 3 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
    fprintf(stderr, "usage: bench_frames DB SCENE [FRAMES] [WxH]\n");
    return argc < 3 ? 2 : 0;
  }
  int frames = argc > 3 ? atoi(argv[3]) : 10, w = 640, h = 480;
  if (argc > 4 && sscanf(argv[4], "%dx%d", &w, &h) != 2)
    die(argv[4], NULL);
  satf_error err;
  bench_setup b = bench_open("bench_frames", argv[1], argv[2], w, h);
  satf_renderer *r = b.r;
  satf_scene_camera start = *satf_renderer_camera(r);
  satf_frame_timing sum[NSIT], t;
  memset(sum, 0, sizeof sum);
  if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
    die("render", &err);
  float step = 2.0f * SATF_PI_F / 180.0f;
  for (int f = 0; f < frames; f++)
    for (int s = 0; s < NSIT; s++) {
      r->instanced = s != ORBIT_PER_INSTANCE;
      r->incremental = s != STILL_FULL;
      if (s == ORBIT || s == ORBIT_PER_INSTANCE)
        bench_turn(satf_renderer_camera(r), step);
      if (s == STILL || s == STILL_FULL) { /* a frame at the same view */
        if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
          die("render", &err);
      }
      if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
        die("render", &err);
      add(&sum[s], &t);
    }
  printf("%s: %ld clusters, %ld HSVs, %dx%d, %d frames each, %d threads\n",
         argv[2], r->stats.clusters, r->stats.hsvs, w, h, frames, r->threads);
  printf("%-16s %8s %7s %7s %7s %7s %7s %7s\n", "frame", "look-ups", "I ms",
         "C ms", "M ms", "S ms", "L ms", "all ms");
  for (int s = 0; s < NSIT; s++) {
    double n = frames;
    printf("%-16s %8.0f %7.1f %7.1f %7.1f %7.1f %7.1f %7.1f\n", NAMES[s],
           (double)sum[s].lookups / n, sum[s].index_ms / n, sum[s].maps_ms / n,
           sum[s].upload_ms / n, sum[s].shadow_ms / n, sum[s].lighting_ms / n,
           sum[s].total_ms / n);
  }
  *satf_renderer_camera(r) = start;
  r->instanced = r->incremental = 1;
  if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
    die("render", &err);
  long frags, pixels, saturated;
  fragment_stats(r, &frags, &pixels, &saturated);
  printf("fragments %ld on %ld pixels (%.1f%% of the frame, %.2f per covered "
         "pixel); rays stopped by early termination %.1f%%\n",
         frags, pixels, 100.0 * (double)pixels / ((double)w * h),
         pixels ? (double)frags / (double)pixels : 0.0,
         frags ? 100.0 * (double)saturated / (double)frags : 0.0);
  printf("shading pass draw calls: %d instanced, %d one per instance\n",
         draw_calls(r, 1), draw_calls(r, 0));
  bench_close(&b);
  return 0;
}
