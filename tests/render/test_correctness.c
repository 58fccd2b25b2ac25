/* test_correctness.c - rendering cases that were once wrong:
 * mirrored instances, non-uniform instance scale, rays leaving through a
 * cluster's end (phantom caps) and entering through it (a cluster seen
 * end-on), a lone cluster under the deep opacity map
 * (self-shadowing counted once), a cluster lit along its axis, and
 * anti-aliasing by jittered samples. */
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
#include "satf/math.h"
#include "satf/render.h"
#include "test_util.h"

#define W 160
#define H 120

static fixture_gl *gl;

static int setup(void **state) {
  (void)state;
  return (gl = fixture_gl_create(W, H)) ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  fixture_gl_free(gl);
  return 0;
}

/* Renders `json` (with AOVs when aovs) at W x H; samples > 0 overrides
 * the scene's, cluster_shadows < 0 keeps the scene's. */
static satf_image *render_json(const char *json, int aovs, int samples,
                               int cluster_shadows) {
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  satf_renderer *r = NULL;
  satf_error err;
  if (satf_renderer_create(s, gl->db, W, H, 0, &r, &err) != SATF_OK)
    fail_msg("%s", err.message);
  if (samples > 0)
    satf_renderer_set_samples(r, samples);
  if (cluster_shadows >= 0)
    satf_renderer_effects(r)->cluster_shadows = cluster_shadows;
  satf_image *img = NULL;
  satf_frame_timing t;
  if (satf_renderer_render_image(r, aovs, &img, &t, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  return img;
}

/* One bent, twisted cluster; `instance` is its instance object and the
 * camera and light are given, so a scene and its mirror image can be
 * written. */
static void one_cluster(char *buf, size_t size, const char *instance,
                        float cam_x, float light_x) {
  snprintf(
      buf, size,
      "{\"macro_clusters\": [{\"prototype\": {"
      "  \"trajectory\": [[0.5, -3, 0], [1.0, 0, 0.3], [0.6, 3, 0]],"
      "  \"a\": 1.0, \"b\": 0.7, \"twist\": [0, 1.2, 2.4],"
      "  \"shell\": {\"layers\": 4, \"st\": 12, \"su\": 10, \"core\": 0.4},"
      "  \"density\": {\"strands\": 800, \"seed\": 5,"
      "               \"strand_width\": 0.05}},"
      "  \"instances\": [%s]}],"
      " \"camera\": {\"position\": [%g, 1, 12], \"target\": [%g, 0, 0],"
      "              \"fov_y\": 40},"
      " \"lights\": [{\"direction\": [%g, -0.4, -0.85]}],"
      " \"image\": {\"width\": %d, \"height\": %d}}",
      instance, cam_x, cam_x, light_x, W, H);
}

/* A mirrored instance seen by a mirrored camera under a mirrored light is
 * the mirror image of the plain one, pixel for pixel: the proxy's outward
 * faces must stay the ones drawn (glFrontFace), or shading starts at the
 * far face with the wrong normal and depth. */
static void test_mirrored_instance(void **state) {
  (void)state;
  char plain[2048], mirrored[2048];
  one_cluster(plain, sizeof plain, "{}", 1.5f, -0.3f);
  one_cluster(mirrored, sizeof mirrored, "{\"scale\": [-1, 1, 1]}", -1.5f,
              0.3f);
  satf_image *a = render_json(plain, 0, 0, -1);
  satf_image *b = render_json(mirrored, 0, 0, -1);
  const char *ch[4] = {"R", "G", "B", "A"};
  double worst = 0.0, sum = 0.0, covered = 0.0;
  for (int c = 0; c < 4; c++) {
    const float *pa = fixture_plane(a, ch[c]), *pb = fixture_plane(b, ch[c]);
    for (int y = 0; y < H; y++)
      for (int x = 0; x < W; x++) {
        double d = fabs(pa[y * W + x] - pb[y * W + (W - 1 - x)]);
        sum += d;
        worst = d > worst ? d : worst;
        if (c == 3)
          covered += pa[y * W + x];
      }
  }
  double mean = sum / (4.0 * W * H);
  printf("mirror: %.0f covered pixels, mean |diff| %.5f, max %.4f\n", covered,
         mean, worst);
  assert_true(covered > 500.0);
  assert_true(mean < 2e-3);
  satf_image_destroy(a);
  satf_image_destroy(b);
}

/* The renderer refuses a cluster instance with non-uniform scale or shear
 * (its angles are measured in the prototype's frame), naming it, also
 * when an animation key brings it in; uniform scale and mirrors render. */
static void test_non_uniform_refused(void **state) {
  (void)state;
  static const char *const bad[] = {"{\"scale\": [1, 2, 1]}",
                                    "{\"matrix\": [1, 0.5, 0, 0, 0, 1, 0, 0, "
                                    "0, 0, 1, 0, 0, 0, 0, 1]}"};
  static const char *const good[] = {"{\"scale\": 2}",
                                     "{\"scale\": [-2, 2, 2]}",
                                     "{\"matrix\": [0, -2, 0, 1, 2, 0, 0, 0, "
                                     "0, 0, 2, 0, 0, 0, 0, 1]}"};
  char json[2048];
  satf_error err;
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    one_cluster(json, sizeof json, bad[i], 0.0f, 0.3f);
    satf_scene *s = fixture_scene(json);
    assert_non_null(s);
    satf_renderer *r = NULL;
    assert_int_not_equal(satf_renderer_create(s, gl->db, W, H, 0, &r, &err),
                         SATF_OK);
    assert_null(r);
    printf("refused: %s\n", err.message);
    assert_non_null(strstr(err.message, "non-uniform scale or shear"));
    assert_non_null(strstr(err.message, "macro_clusters[0]"));
    satf_scene_destroy(s);
  }
  for (size_t i = 0; i < sizeof good / sizeof *good; i++) {
    one_cluster(json, sizeof json, good[i], 0.0f, 0.3f);
    satf_scene *s = fixture_scene(json);
    assert_non_null(s);
    satf_renderer *r = NULL;
    assert_int_equal(satf_renderer_create(s, gl->db, W, H, 0, &r, &err),
                     SATF_OK);
    satf_renderer_destroy(r);
    satf_scene_destroy(s);
  }
  /* keyed: similar at frame 1, stretched at frame 2 */
  one_cluster(json, sizeof json,
              "{\"keys\": [{\"frame\": 1}, {\"frame\": 2, \"scale\": "
              "[1, 1, 3]}]}",
              0.0f, 0.3f);
  char *end = strrchr(json, '}');
  snprintf(end, sizeof json - (size_t)(end - json),
           ", \"animation\": {\"frames\": [1, 2]}}");
  satf_scene *s = fixture_scene(json), *f1 = NULL, *f2 = NULL;
  assert_non_null(s);
  assert_int_equal(satf_scene_at_frame(s, 1.0, &f1, &err), SATF_OK);
  assert_int_equal(satf_scene_at_frame(s, 2.0, &f2, &err), SATF_OK);
  satf_renderer *r = NULL;
  assert_int_equal(satf_renderer_create(f1, gl->db, W, H, 0, &r, &err),
                   SATF_OK);
  int rebuilt = 0;
  assert_int_not_equal(satf_renderer_set_scene(r, f2, &rebuilt, &err), SATF_OK);
  assert_non_null(strstr(err.message, "non-uniform scale or shear"));
  satf_renderer_destroy(r);
  satf_scene_destroy(f1);
  satf_scene_destroy(f2);
  satf_scene_destroy(s);
}

/* A sparse straight cluster seen from above its root end: rays that
 * enter its side near the root leave through the root's open end, where
 * there are no strands. Their alpha must fall towards that end (only the
 * front halves of the shells are met before the ray leaves), not stay at
 * the middle's value, as clamping t to the end row did. */
static void test_no_phantom_caps(void **state) {
  (void)state;
  const char *json =
      "{\"macro_clusters\": [{\"prototype\": {"
      "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 0.8,"
      "  \"shell\": {\"layers\": 4, \"st\": 16, \"su\": 10},"
      "  \"density\": {\"strands\": 120, \"seed\": 3,"
      "               \"strand_width\": 0.02}}}],"
      " \"camera\": {\"position\": [0, -7, 6], \"target\": [0, 0, 0],"
      "              \"fov_y\": 50},"
      " \"lights\": [{\"direction\": [0, 0, -1]}],"
      " \"effects\": {\"cluster_shadows\": false},"
      " \"image\": {\"width\": 160, \"height\": 120}}";
  satf_image *img = render_json(json, 0, 0, -1);
  const float *A = fixture_plane(img, "A");
  /* the run of covered rows down the image's middle columns, mean alpha
   * per row over a band of columns around the axis */
  double row_alpha[H];
  int first = -1, last = -1;
  for (int y = 0; y < H; y++) {
    double s = 0.0;
    for (int x = W / 2 - 4; x < W / 2 + 4; x++)
      s += A[y * W + x];
    row_alpha[y] = s / 8.0;
    if (row_alpha[y] > 0.02) {
      if (first < 0)
        first = y;
      last = y;
    }
  }
  assert_true(first >= 0 && last - first > 20);
  int n = last - first + 1, band = n / 10;
  double lo = 0.0, mid = 0.0, hi = 0.0;
  for (int k = 0; k < band; k++) {
    lo += row_alpha[first + k];
    hi += row_alpha[last - k];
    mid += row_alpha[first + n / 2 - band / 2 + k];
  }
  lo /= band;
  mid /= band;
  hi /= band;
  printf("alpha down the axis: first rows %.3f, middle %.3f, last rows "
         "%.3f\n",
         lo, mid, hi);
  /* the first rows hold the root end, whose rays leave through the open
   * end: clearly less alpha there (clamped, they had more than the
   * middle: 0.74 against 0.65) */
  assert_true(lo < 0.6 * mid);
  satf_image_destroy(img);
}

/* A cluster seen end-on, down its axis: its walls face away from the eye,
 * so only the proxy's end cap (hierarchy.c: proxy_caps) lets the rays into
 * it, which then meet its shells below the cap. Without the caps the
 * culled walls left a hole the shape of the cluster: alpha 0. */
static void test_end_on_cluster_covered(void **state) {
  (void)state;
  const char *json =
      "{\"macro_clusters\": [{\"prototype\": {"
      "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 1.0,"
      "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 12},"
      "  \"density\": {\"strands\": 800, \"seed\": 4,"
      "               \"strand_width\": 0.05}}}],"
      " \"camera\": {\"position\": [0, 9, 0], \"target\": [0, 0, 0],"
      "              \"up\": [0, 0, -1], \"fov_y\": 40},"
      " \"lights\": [{\"direction\": [0.3, -0.9, -0.3]}],"
      " \"image\": {\"width\": 160, \"height\": 120}}";
  satf_image *img = render_json(json, 0, 0, -1);
  const float *A = fixture_plane(img, "A");
  /* the cap's disc: radius 1 at distance 7 under a 40 degree field */
  float rpx = 1.0f / (7.0f * tanf(20.0f * SATF_PI_F / 180.0f)) * 0.5f * H;
  int inside = 0;
  double alpha = 0.0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      float dx = (float)x + 0.5f - 0.5f * W, dy = (float)y + 0.5f - 0.5f * H;
      if (dx * dx + dy * dy > 0.8f * 0.8f * rpx * rpx)
        continue;
      inside++;
      alpha += A[y * W + x];
    }
  alpha /= inside > 0 ? inside : 1;
  printf("end-on: mean alpha %.3f over %d pixels within the disc\n", alpha,
         inside);
  /* rays down the axis run along the strands and meet few of them (the
   * strand path sees their ends: 800 of width 0.05 cover half the disc);
   * the oblique ones away from the middle cross the shells */
  assert_true(inside > 100);
  assert_true(alpha > 0.3);
  satf_image_destroy(img);
}

/* A lone cluster is shadowed by its records and eq. 12's s-map only: the
 * deep opacity map, which owns the other clusters' shadows, must not
 * darken it a second time. */
static void test_lone_cluster_dom(void **state) {
  (void)state;
  char json[2048];
  one_cluster(json, sizeof json, "{}", 1.5f, -0.3f);
  satf_image *on = render_json(json, 1, 0, 1);
  satf_image *off = render_json(json, 1, 0, 0);
  const float *a = fixture_plane(on, "shadow.Y"),
              *b = fixture_plane(off, "shadow.Y"),
              *alpha = fixture_plane(off, "alpha.Y");
  double diff = 0.0, cover = 0.0, worst = 0.0;
  for (int i = 0; i < W * H; i++) {
    double d = fabs(a[i] - b[i]);
    diff += d;
    cover += alpha[i];
    worst = d > worst ? d : worst;
  }
  printf("lone cluster: shadow AOV with and without the DOM differs by "
         "%.4f on average over %.0f covered pixels (max %.4f)\n",
         diff / cover, cover, worst);
  assert_true(cover > 500.0);
  assert_true(diff / cover < 0.01);
  satf_image_destroy(on);
  satf_image_destroy(off);
}

/* A cluster lit nearly along its axis, from the end where a dense cluster
 * lies across the light: the look-up for its shadow is taken where the
 * light's ray leaves the cluster, which on the local elliptic cylinder
 * runs off to infinity as the light turns along the axis (here 16 units
 * away, past the other cluster, so it cast no shadow). Taken within the
 * widest chord, the map counts the hair beyond it, the other cluster's
 * included. */
static void axis_lit(char *buf, size_t size, int occluder) {
  snprintf(buf, size,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 0.5,"
           "  \"shell\": {\"layers\": 4, \"st\": 12, \"su\": 10},"
           "  \"density\": {\"strands\": 400, \"seed\": 4,"
           "               \"strand_width\": 0.03}}}%s],"
           " \"camera\": {\"position\": [0, 0, 14], \"target\": [0, 0, 0],"
           "              \"fov_y\": 50},"
           " \"lights\": [{\"direction\": [-0.03, -1, 0]}],"
           " \"image\": {\"width\": %d, \"height\": %d}}",
           occluder ? ", {\"prototype\": {"
                      "  \"trajectory\": [[-3, 5, 0], [3, 5, 0]], \"a\": 1.5,"
                      "  \"shell\": {\"layers\": 4, \"st\": 12, \"su\": 16},"
                      "  \"density\": {\"strands\": 6000, \"seed\": 6,"
                      "               \"strand_width\": 0.05}}}"
                    : "",
           W, H);
}

static void test_shadow_along_axis(void **state) {
  (void)state;
  char json[4096];
  axis_lit(json, sizeof json, 0);
  satf_image *alone = render_json(json, 1, 0, 1);
  axis_lit(json, sizeof json, 1);
  satf_image *under = render_json(json, 1, 0, 1);
  const float *a = fixture_plane(alone, "shadow.Y"),
              *b = fixture_plane(under, "shadow.Y"),
              *cover = fixture_plane(alone, "alpha.Y");
  double sa = 0.0, sb = 0.0, n = 0.0;
  for (int i = 0; i < W * H; i++)
    if (cover[i] > 0.5f) { /* the lit cluster's pixels: the other lies above */
      sa += a[i];
      sb += b[i];
      n += 1.0;
    }
  printf("lit along its axis: shadow AOV %.4f alone, %.4f under the other "
         "cluster (%.0f pixels)\n",
         sa / n, sb / n, n);
  assert_true(n > 200.0);
  assert_true(sa / n > 0.05);
  /* 0.004 against 0.57 alone; the exit unbounded left 0.22 */
  assert_true(sb < 0.1 * sa);
  satf_image_destroy(alone);
  satf_image_destroy(under);
}

/* Pixels whose alpha is strictly between the two bounds. */
static int partial_pixels(const satf_image *img) {
  const float *A = fixture_plane(img, "A");
  int n = 0;
  for (int i = 0; i < W * H; i++)
    n += A[i] > 0.05f && A[i] < 0.95f;
  return n;
}

/* An opaque square seen at an angle: one sample per pixel gives a hard,
 * aliased edge (alpha 0 or 1); eight jittered samples give fractional
 * coverage along the whole edge and keep the covered area. */
static void test_samples_antialias(void **state) {
  (void)state;
  char obj[512], json[2048];
  test_path(obj, sizeof obj, "satf-correctness-square.obj");
  const char *square = "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nf 1 2 3\n"
                       "f 1 3 4\n";
  test_write_file(obj, square, strlen(square));
  for (int samples = 1; samples <= 8; samples *= 8) {
    snprintf(json, sizeof json,
             "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
             "[[0, -1, -3], [0, 1, -3]], \"a\": 0.3, \"density\": "
             "{\"strands\": 50}}}],"
             " \"meshes\": [{\"file\": \"%s\", \"transform\": {\"rotate\": "
             "{\"axis\": [0, 0, 1], \"angle\": 17}}}],"
             " \"camera\": {\"position\": [0, 0, 10], \"target\": [0, 0, 0],"
             "              \"fov_y\": 40},"
             " \"lights\": [{\"direction\": [0, 0, -1]}],"
             " \"image\": {\"width\": %d, \"height\": %d, \"samples\": %d}}",
             obj, W, H, samples);
    satf_image *img = render_json(json, 0, 0, -1);
    const float *A = fixture_plane(img, "A");
    double area = 0.0;
    for (int i = 0; i < W * H; i++)
      area += A[i];
    int partial = partial_pixels(img);
    printf("%d sample(s): %d partly covered pixels, area %.1f\n", samples,
           partial, area);
    /* the square's edge is about 4 x 4 / tan(20 deg) * H / 2 / 4 pixels */
    if (samples == 1)
      assert_true(partial < 10);
    else
      assert_true(partial > 150);
    static double area1;
    if (samples == 1)
      area1 = area;
    else
      assert_true(fabs(area - area1) < 0.01 * area1);
    satf_image_destroy(img);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mirrored_instance),
      cmocka_unit_test(test_non_uniform_refused),
      cmocka_unit_test(test_no_phantom_caps),
      cmocka_unit_test(test_end_on_cluster_covered),
      cmocka_unit_test(test_lone_cluster_dom),
      cmocka_unit_test(test_shadow_along_axis),
      cmocka_unit_test(test_samples_antialias),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
