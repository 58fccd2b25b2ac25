/* test_sparse.c - a cluster of few strands looks like few strands of the
 * same hair: rendered with 3000, 300 and 30 strands, same
 * material and light, its coverage drops while the colour of the hair it
 * covers, sum(premultiplied rgb) / sum(alpha), stays but for the strands'
 * shadows on each other, which only darken dense hair. Whole frames on Mesa's
 * llvmpipe through a headless EGL context, with a small database built in
 * the test. */
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

#include "render_fixture.h"
#include "satf/common.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "test_util.h"

#define W 96
#define H 128
#define COUNTS 3

static const int strand_counts[COUNTS] = {3000, 300, 30};

/* One straight cluster seen side-on, lit from the upper left and front;
 * black background, so the frame's RGB is the premultiplied hair colour.
 * Everything but the strand count and the eq. 12 switch is fixed. */
static const char *scene_format =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, -4, 0], [0, 4, 0]], \"a\": 1.3, \"b\": 1.0,"
    "  \"shell\": {\"layers\": 8, \"st\": 16, \"su\": 20, \"core\": 0.3},"
    "  \"density\": {\"strands\": %d, \"seed\": 61, \"layout\": \"uniform\","
    "               \"strand_width\": 0.03}}}],"
    " \"camera\": {\"position\": [0, 0, 20], \"target\": [0, 0, 0],"
    "              \"fov_y\": 30},"
    " \"lights\": [{\"direction\": [-0.45, -0.35, -0.82]}],"
    " \"background\": [0, 0, 0], \"effects\": {\"self_shadow\": %s},"
    " \"image\": {\"width\": 96, \"height\": 128}}";

typedef fixture_gl fixture;

FIXTURE_GL_GROUP(W, H)

/* What a frame shows of the cluster: the pixels it covers noticeably, their
 * mean alpha, and the mean colour of the hair there, sum(rgb) / sum(alpha)
 * (the colour per unit coverage, i.e. per strand). */
typedef struct cluster_look {
  size_t covered;
  double coverage; /* sum of alpha over the frame, in pixels */
  double alpha;    /* mean alpha over covered pixels */
  double rgb[3];   /* sum(premultiplied rgb) / sum(alpha) over them */
  double luma;     /* Rec. 709 luminance of rgb */
} cluster_look;

static cluster_look look_at(const satf_image *img) {
  static const char *const names[3] = {"R", "G", "B"};
  const float *a = fixture_plane(img, "A");
  cluster_look lk = {0};
  double sum_a = 0.0, sum_c[3] = {0.0, 0.0, 0.0};
  for (size_t i = 0; i < (size_t)W * H; i++) {
    lk.coverage += a[i];
    /* 0.02: below it a pixel's colour is mostly rounding of tiny values */
    if (!(a[i] > 0.02f))
      continue;
    lk.covered++;
    sum_a += a[i];
    for (int c = 0; c < 3; c++)
      sum_c[c] += fixture_plane(img, names[c])[i];
  }
  if (lk.covered == 0)
    return lk;
  lk.alpha = sum_a / (double)lk.covered;
  for (int c = 0; c < 3; c++)
    lk.rgb[c] = sum_c[c] / sum_a;
  lk.luma = 0.2126 * lk.rgb[0] + 0.7152 * lk.rgb[1] + 0.0722 * lk.rgb[2];
  return lk;
}

static cluster_look render_cluster(const fixture *f, int strands,
                                   int self_shadow) {
  char json[2048];
  snprintf(json, sizeof json, scene_format, strands,
           self_shadow ? "true" : "false");
  satf_scene *scene = fixture_scene(json);
  assert_non_null(scene);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, 0, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  cluster_look lk = look_at(img);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
  return lk;
}

/* Renders the cluster with 3000, 300 and 30 strands: coverage must drop,
 * the luminance of the colour per strand be at least 0.95 times the
 * densest's (fewer strands shadow less) and at most 1 + `tolerance` times,
 * and its hue (each channel over the luminance) within 5%. */
static void check_counts(const fixture *f, int self_shadow, double tolerance) {
  cluster_look lk[COUNTS];
  for (int n = 0; n < COUNTS; n++) {
    lk[n] = render_cluster(f, strand_counts[n], self_shadow);
    printf("eq. 12 %s, %4d strands: %zu px covered, coverage %.0f px, mean "
           "alpha %.3f, colour/alpha (%.4f %.4f %.4f), luminance %.4f\n",
           self_shadow ? "on " : "off", strand_counts[n], lk[n].covered,
           lk[n].coverage, lk[n].alpha, lk[n].rgb[0], lk[n].rgb[1],
           lk[n].rgb[2], lk[n].luma);
    assert_true(lk[n].covered > 200);
    assert_true(lk[n].luma > 0.0);
  }
  for (int n = 1; n < COUNTS; n++) {
    /* more transparent as a whole */
    assert_true(lk[n].coverage < 0.9 * lk[n - 1].coverage);
    assert_true(lk[n].alpha < lk[n - 1].alpha - 0.05);
    /* the same colour per strand, but for shadows */
    double ratio = lk[n].luma / lk[0].luma;
    printf("%d / %d strands: luminance ratio %.3f\n", strand_counts[n],
           strand_counts[0], ratio);
    assert_true(ratio > 0.95 && ratio < 1.0 + tolerance);
    for (int c = 0; c < 3; c++)
      assert_near(lk[n].rgb[c] / lk[n].luma, lk[0].rgb[c] / lk[0].luma,
                  0.05 * lk[0].rgb[c] / lk[0].luma);
  }
  /* and darker as a whole: the premultiplied colour per covered pixel */
  assert_true(lk[COUNTS - 1].luma * lk[COUNTS - 1].alpha <
              0.8 * lk[0].luma * lk[0].alpha);
}

/* Tolerances from measurements (this fixture database). With eq. 12 off,
 * the colour per strand of 300 and 30 strands is 1.05 and 1.12 times that
 * of 3000: the records keep the shadows the strands of a sector cast on
 * each other, which dense hair has more of, and reflectance is scaled as
 * hair nothing shadows (maps.c, reflectance_scale), as the strand
 * reference path lights a strand. With reflectance normalised by each
 * database sample's own mean (which took those shadows out on average and
 * brightened dense hair lit from the eye's side) it was 0.93 and 1.06; with
 * one scale from the opaque records, 1.11 and 1.30, which 15% fails. */
static void test_colour_per_strand(void **state) {
  check_counts(*state, 0, 0.15);
}

/* With eq. 12 on, a dense cluster's deeper strands are also shadowed by the
 * layers above them (mean s-map transmittance of the visible hair 0.82 at
 * 3000 strands, 0.90 at 30), which the paper intends: measured 1.04 and
 * 1.22 (0.92 and 1.13 with each sample's own scale), so 25%. Before the
 * fix: 1.10 and 1.38, and 30 strands paler (the
 * strands at the cluster's back showed a white primary highlight: their
 * tangent was shifted along the outward normal, away from the viewer). */
static void test_colour_per_strand_self_shadowed(void **state) {
  check_counts(*state, 1, 0.25);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_colour_per_strand),
      cmocka_unit_test(test_colour_per_strand_self_shadowed),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
