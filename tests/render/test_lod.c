/* test_lod.c - the level of detail (online/render/lod.c):
 * the level and proxy chosen for known sizes on screen, the layers' shares
 * continuous in the level and summing to the layer count, the image
 * continuous across the transition bands (no popping: the level swept
 * in small steps changes the frame in small steps, none much larger than
 * the others), and a small render with the level of detail within the
 * issue's bound of full detail (soft IoU >= 0.97, SSIM >= 0.95). */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
/* cmocka needs the headers above first */
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metrics.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "test_util.h"

#define W 160
#define H 120

static void level_choice(void **state) {
  (void)state;
  lod_params p = lod_defaults();
  p.full_px = 24.0f;
  /* wide: every layer; each halving of the width one level more */
  assert_float_equal(lod_level(100.0f, 4, &p), 0.0f, 0.0f);
  assert_float_equal(lod_level(24.0f, 4, &p), 0.0f, 0.0f);
  assert_float_equal(lod_level(12.0f, 4, &p), 1.0f, 1e-6f);
  assert_float_equal(lod_level(24.0f / sqrtf(2.0f), 4, &p), 0.5f, 1e-5f);
  /* capped where one layer stands for all: 2 for 4 layers, 2 for 3, 3
   * for 5; one layer has no levels */
  assert_float_equal(lod_level(1.0f, 4, &p), 2.0f, 0.0f);
  assert_float_equal(lod_level(1.0f, 3, &p), 2.0f, 0.0f);
  assert_float_equal(lod_level(1.0f, 5, &p), 3.0f, 0.0f);
  assert_float_equal(lod_level(0.0f, 4, &p), 2.0f, 0.0f);
  assert_float_equal(lod_level(1.0f, 1, &p), 0.0f, 0.0f);
  /* proxies: the thin ring at most thin_px wide, on every second row
   * when its two-row bands depart at most sag_px from the shell */
  p.thin_px = 8.0f;
  p.sag_px = 0.1f;
  p.hysteresis = 0.15f;
  assert_int_equal(lod_proxy(100.0f, 0.0f, -1, &p), LOD_PROXY_FULL);
  assert_int_equal(lod_proxy(8.5f, 0.0f, -1, &p), LOD_PROXY_FULL);
  assert_int_equal(lod_proxy(6.0f, 1.0f, -1, &p), LOD_PROXY_THIN);
  assert_int_equal(lod_proxy(6.0f, 0.05f, -1, &p), LOD_PROXY_THIN_HALF_ROWS);
  /* hysteresis: 6% over thin_px, one drawn thin stays thin and one drawn
   * full stays full; 20% over it, the thin one goes back */
  assert_int_equal(lod_proxy(8.5f, 1.0f, LOD_PROXY_THIN, &p), LOD_PROXY_THIN);
  assert_int_equal(lod_proxy(8.5f, 1.0f, LOD_PROXY_FULL, &p), LOD_PROXY_FULL);
  assert_int_equal(lod_proxy(9.6f, 1.0f, LOD_PROXY_THIN, &p), LOD_PROXY_FULL);
  assert_int_equal(lod_proxy(6.0f, 0.108f, LOD_PROXY_THIN_HALF_ROWS, &p),
                   LOD_PROXY_THIN_HALF_ROWS);
  assert_int_equal(lod_proxy(6.0f, 0.108f, LOD_PROXY_THIN, &p), LOD_PROXY_THIN);
  /* the deep opacity map's proxy is never chosen */
  assert_int_equal(lod_proxy(6.0f, 0.05f, LOD_PROXY_DOM, &p),
                   LOD_PROXY_THIN_HALF_ROWS);
}

/* Every layer count 1-9, the level in steps of 1/512 up to its cap: the
 * shares sum to the layer count, move by at most (layers x step) per step
 * (continuous), are whole at whole levels, and at the cap only the
 * outermost layer is read. */
static void shares(void **state) {
  (void)state;
  for (int layers = 1; layers <= 9; layers++) {
    int cap = 0;
    while ((1 << cap) < layers)
      cap++;
    float prev[9];
    const float step = 1.0f / 512.0f;
    for (int s = 0; s <= cap * 512; s++) {
      float level = (float)s * step, sum = 0.0f;
      for (int k = 0; k < layers; k++) {
        float e = lod_layer_share(level, k, layers);
        assert_true(e >= 0.0f && e <= (float)layers);
        if (s > 0)
          assert_true(fabsf(e - prev[k]) <= (float)layers * step * 1.001f);
        if (s % 512 == 0)
          assert_float_equal(e, roundf(e), 1e-6f);
        prev[k] = e;
        sum += e;
      }
      assert_float_equal(sum, (float)layers, 1e-4f);
    }
    for (int k = 0; k < layers; k++)
      assert_float_equal(lod_layer_share((float)cap, k, layers),
                         k == layers - 1 ? (float)layers : 0.0f, 1e-6f);
  }
  /* level 1 of four layers: the outermost and the second innermost, two
   * each */
  assert_float_equal(lod_layer_share(1.0f, 3, 4), 2.0f, 0.0f);
  assert_float_equal(lod_layer_share(1.0f, 2, 4), 0.0f, 0.0f);
  assert_float_equal(lod_layer_share(1.0f, 1, 4), 2.0f, 0.0f);
  assert_float_equal(lod_layer_share(1.0f, 0, 4), 0.0f, 0.0f);
}

/* A row of nine four-layer clusters, a few pixels wide at W x H. */
static const char *const SCENE =
    "{\"macro_clusters\": ["
    " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.4, 0, 0.2], [0, 2, 0]],"
    "   \"a\": 0.45, \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 8},"
    "   \"density\": {\"strands\": 120, \"seed\": 7}},"
    "  \"instances\": ["
    "   {\"translate\": [-4, 0, 0]}, {\"translate\": [-3, 0, 0.5]},"
    "   {\"translate\": [-2, 0, -0.5]}, {\"translate\": [-1, 0, 0]},"
    "   {\"translate\": [0, 0, 0.4]}, {\"translate\": [1, 0, -0.4]},"
    "   {\"translate\": [2, 0, 0]}, {\"translate\": [3, 0, 0.5]},"
    "   {\"translate\": [4, 0, 0]}]}],"
    " \"camera\": {\"position\": [0, 1, 30], \"target\": [0, 0, 0],"
    "            \"fov_y\": 30},"
    " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"
    " \"background\": [0, 0, 0]}";

typedef struct fixture {
  fixture_gl *gl;
  satf_scene *scene;
  satf_renderer *r;
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  satf_error err;
  if (!f || !(f->gl = fixture_gl_create(W, H)) ||
      !(f->scene = fixture_scene(SCENE)) ||
      satf_renderer_create(f->scene, f->gl->db, W, H, 2, &f->r, &err) !=
          SATF_OK)
    return -1;
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  satf_renderer_destroy(f->r);
  satf_scene_destroy(f->scene);
  fixture_gl_free(f->gl);
  free(f);
  return 0;
}

static satf_image *render(satf_renderer *r) {
  satf_image *img = NULL;
  satf_error err;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fprintf(stderr, "%s\n", err.message);
  return img;
}

/* Mean |a - b| over R, G, B, A. */
static double mean_diff(const satf_image *a, const satf_image *b) {
  static const char *const ch[4] = {"R", "G", "B", "A"};
  double sum = 0.0;
  size_t n = (size_t)W * H;
  for (int c = 0; c < 4; c++) {
    const float *pa = fixture_plane(a, ch[c]), *pb = fixture_plane(b, ch[c]);
    for (size_t i = 0; i < n; i++)
      sum += fabs((double)pa[i] - (double)pb[i]);
  }
  return sum / (4.0 * (double)n);
}

/* The clusters' width on screen stays; the threshold full_px moves so the
 * level sweeps 0 to 2 in steps of 1/8 (the proxy does not depend on it).
 * A level switched at whole levels would put the sweep's change into two
 * steps of sixteen. */
static void no_popping(void **state) {
  fixture *f = *state;
  satf_renderer *r = f->r;
  satf_renderer_set_lod(r, 1);
  satf_render_stats s;
  /* the clusters' width from the level at full_px 1e4 (capped: none) */
  /* full_px from the narrowest cluster's width (level 0 everywhere) to
   * four times the widest's (every cluster one layer) */
  float lo = 1e30f, hi = 0.0f, w, sag;
  for (int i = 0; i < r->ninsts; i++) {
    lod_screen_size(r, i, &w, &sag);
    lo = w < lo ? w : lo;
    hi = w > hi ? w : hi;
  }
  r->lod_opt.full_px = lo;
  satf_image *prev = render(r);
  assert_non_null(prev);
  satf_renderer_stats(r, &s);
  assert_int_equal(s.lod_levels[0], 9);
  /* at level 0 everywhere the shading program with the level of detail
   * compiled in (--lod on) and the one without (off: glsl/shade_fs.glsl,
   * LOD 0) draw the same frame */
  satf_renderer_set_lod(r, 0);
  satf_image *off = render(r);
  assert_non_null(off);
  printf("lod on at level 0 vs off: mean |difference| %g\n",
         mean_diff(prev, off));
  assert_true(mean_diff(prev, off) == 0.0);
  satf_image_destroy(off);
  satf_renderer_set_lod(r, 1);
  enum { STEPS = 24 };
  double steps[STEPS], total = 0.0, most = 0.0;
  for (int i = 0; i < STEPS; i++) {
    r->lod_opt.full_px =
        lo * powf(4.0f * hi / lo, (float)(i + 1) / (float)STEPS);
    satf_image *img = render(r);
    assert_non_null(img);
    steps[i] = mean_diff(prev, img);
    total += steps[i];
    most = steps[i] > most ? steps[i] : most;
    satf_image_destroy(prev);
    prev = img;
  }
  satf_renderer_stats(r, &s);
  assert_int_equal(s.lod_single, 9);
  satf_image_destroy(prev);
  for (int i = 0; i < STEPS; i++)
    printf("%.2g ", steps[i]);
  printf("(mean |step| over the sweep)\n");
  /* the sweep changes the frame, and no step by more than three times
   * the mean step */
  assert_true(total > 1e-3);
  assert_true(most <= 3.0 * total / STEPS);
}

/* Eight dense clusters receding from 8 to 60 units before the camera:
 * 6 to 27 pixels wide at W x H, so the near ones read every layer and the
 * far ones fewer, as in a hairstyle seen whole. */
static const char *const DEPTH =
    "{\"macro_clusters\": ["
    " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.4, 0, 0.2], [0, 2, 0]],"
    "   \"a\": 0.45, \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 8},"
    "   \"density\": {\"strands\": 600, \"seed\": 7}},"
    "  \"instances\": ["
    "   {\"translate\": [-1.2, 0, 22]}, {\"translate\": [1.2, 0, 19]},"
    "   {\"translate\": [-2.5, 0, 14]}, {\"translate\": [2.5, 0, 10]},"
    "   {\"translate\": [-4, 0, 4]}, {\"translate\": [4, 0, -4]},"
    "   {\"translate\": [-6, 0, -15]}, {\"translate\": [6, 0, -30]}]}],"
    " \"camera\": {\"position\": [0, 1, 30], \"target\": [0, 0, 0],"
    "            \"fov_y\": 30},"
    " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"
    " \"background\": [0, 0, 0]}";

/* The default thresholds on DEPTH: within the issue's bound of full
 * detail (soft IoU >= 0.97, SSIM >= 0.95), with some clusters reduced. */
static void image_bound(void **state) {
  fixture *f = *state;
  satf_scene *scene = fixture_scene(DEPTH);
  satf_renderer *r = NULL;
  satf_error err;
  assert_non_null(scene);
  assert_int_equal(satf_renderer_create(scene, f->gl->db, W, H, 2, &r, &err),
                   SATF_OK);
  satf_image *full = render(r);
  satf_renderer_set_lod(r, 1);
  satf_image *lod = render(r);
  assert_non_null(full);
  assert_non_null(lod);
  satf_render_stats s;
  satf_renderer_stats(r, &s);
  compare_image a = fixture_compare_image(full, "full"),
                b = fixture_compare_image(lod, "lod");
  compare_result res;
  assert_int_equal(compare_measure(&a, &b, &res, &err), SATF_OK);
  printf("LOD vs full: soft IoU %.4f, SSIM %.4f; levels %ld/%ld/%ld/%ld, "
         "%ld one layer, %ld thin\n",
         res.iou, res.ssim, s.lod_levels[0], s.lod_levels[1], s.lod_levels[2],
         s.lod_levels[3], s.lod_single, s.lod_coarse);
  assert_true(s.lod_levels[0] >= 2 && s.lod_levels[0] <= 6);
  assert_true(res.union_px > 500);
  assert_true(res.iou >= 0.97);
  assert_true(res.ssim >= 0.95);
  satf_image_destroy(full);
  satf_image_destroy(lod);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest gl[] = {
      cmocka_unit_test(no_popping),
      cmocka_unit_test(image_bound),
  };
  const struct CMUnitTest pure[] = {
      cmocka_unit_test(level_choice),
      cmocka_unit_test(shares),
  };
  int failed = cmocka_run_group_tests(pure, NULL, NULL);
  return failed + cmocka_run_group_tests(gl, setup, teardown);
}
