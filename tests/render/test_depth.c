/* test_depth.c - the depth AOV ("Z" of satf_renderer_render_image with
 * AOVs): hair 8 units in front of the camera over an opaque square 12
 * units away, seen along the z axis. Every drawing path (the clusters
 * composited exactly and by drawing order, a cluster drawn as its
 * strand, the source strands, the textured-patch baseline) gives the hair's
 * depth where the hair is opaque, the square's 12 at its edge (distance along
 * the view axis, as Blender's Z pass: not the 12.2 of the straight line to that
 * point), and 1e10 where nothing is; several samples give the same. Whole
 * frames on Mesa's llvmpipe through a headless EGL context. */
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
#include "satf/render.h"
#include "test_util.h"

#define W 64
#define H 48
#define CAM_Z 10.0f  /* camera on +z looking at the origin */
#define HAIR_Z 2.0f  /* the hair's axis: 8 units away */
#define MESH_Z -2.0f /* the square: 12 units away */
#define FOV_Y 40.0   /* degrees */
#define NO_DEPTH 1e10f

typedef fixture_gl fixture;

FIXTURE_GL_GROUP(W, H)

typedef enum { CLUSTERS, ORDERED, STRANDS, BASELINE, SPARSE } path;
static const char *const path_names[] = {
    "clusters", "clusters (ordered)", "strands", "baseline", "sparse cluster"};

/* The image column of scene point (x, z) on the row through the centre. */
static int column_of(float x, float z) {
  double half = (CAM_Z - z) * tan(0.5 * FOV_Y * 3.14159265358979 / 180.0);
  return (int)floor(0.5 * W + x / half * 0.5 * H);
}

/* The square as an OBJ file (its path into obj). */
static void write_square(char *obj, size_t size) {
  test_path(obj, size, "satf-depth-square.obj");
  char text[256];
  snprintf(text, sizeof text,
           "v -3 -3 %g\nv 3 -3 %g\nv 3 3 %g\nv -3 3 %g\nf 1 2 3\nf 1 3 4\n",
           (double)MESH_Z, (double)MESH_Z, (double)MESH_Z, (double)MESH_Z);
  test_write_file(obj, text, strlen(text));
}

/* The depth plane of the scene drawn by `p` with `samples` samples. */
static satf_image *render_depth(const fixture *f, path p, int samples) {
  char obj[512], json[2048];
  write_square(obj, sizeof obj);
  /* a dense vertical cluster, radius 0.4, on the axis at z = HAIR_Z; or
   * one drawn as its strand (sparse.c), 0.8 wide along that axis */
  const char *density = p == SPARSE ? "{\"type\": \"tracks\", \"slices\": 5, "
                                      "\"strand_width\": 2, \"tracks\": "
                                      "[[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]]}"
                                    : "{\"strands\": 400}";
  snprintf(json, sizeof json,
           "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": "
           "[[0, -2, %g], [0, 2, %g]], \"a\": 0.4, \"density\": %s}}],"
           " \"meshes\": [{\"file\": \"%s\"}],"
           " \"camera\": {\"position\": [0, 0, %g], \"target\": [0, 0, 0],"
           "              \"fov_y\": %g},"
           " \"lights\": [{\"direction\": [0, 0, -1]}],"
           " \"effects\": {\"satf\": %s},"
           " \"image\": {\"width\": %d, \"height\": %d, \"samples\": %d}}",
           (double)HAIR_Z, (double)HAIR_Z, density, obj, (double)CAM_Z, FOV_Y,
           p == BASELINE ? "false" : "true", W, H, samples);
  satf_scene *s = fixture_scene(json);
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
  assert_non_null(r);
  satf_error err;
  if (p == ORDERED)
    satf_renderer_set_composite(r, SATF_COMPOSITE_ORDERED);
  if (p == STRANDS) { /* 41 strands 0.04 wide across the cluster's place */
    enum { N = 41 };
    int counts[N];
    float xyz[N * 2 * 3], width[N * 2];
    for (int i = 0; i < N; i++) {
      counts[i] = 2;
      for (int j = 0; j < 2; j++) {
        float *q = xyz + 6 * i + 3 * j;
        q[0] = -0.4f + 0.8f * (float)i / (N - 1);
        q[1] = j ? 2.0f : -2.0f;
        q[2] = HAIR_Z;
        width[2 * i + j] = 0.04f;
      }
    }
    if (satf_renderer_set_strands(r, N, counts, xyz, width, 0.0f, &err) !=
        SATF_OK)
      fail_msg("%s", err.message);
  }
  satf_image *img = NULL;
  if (satf_renderer_render_image(r, 1, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  remove(obj);
  return img;
}

static void check_path(const fixture *f, path p, int samples) {
  satf_image *img = render_depth(f, p, samples);
  const float *z = fixture_plane(img, "Z");
  const float *a = fixture_plane(img, "A");
  assert_non_null(z);
  int row = H / 2, hair = column_of(0.0f, HAIR_Z);
  int mesh = column_of(2.5f, MESH_Z);
  float zh = z[row * W + hair], zm = z[row * W + mesh], zb = z[0];
  printf("%s, %d sample(s): hair %.4f (alpha %.3f), square %.5f, corner %g\n",
         path_names[p], samples, (double)zh, (double)a[row * W + hair],
         (double)zm, (double)zb);
  /* the hair's front lies between its axis (8) and its outer radius
   * (7.6) */
  if (!(zh > 7.5f && zh < 8.05f))
    fail_msg("%s: hair depth %g, not 7.6 to 8", path_names[p], (double)zh);
  /* planar: 12 all across the square, which a Euclidean distance would
   * put at 12.26 this far off the axis */
  if (fabsf(zm - 12.0f) > 2e-3f)
    fail_msg("%s: square depth %.5f, not 12", path_names[p], (double)zm);
  if (zb != NO_DEPTH)
    fail_msg("%s: background depth %g, not 1e10", path_names[p], (double)zb);
  /* no pixel between hair and square: each holds one of them, or
   * nothing */
  for (int i = 0; i < W * H; i++)
    if (z[i] < 7.5f ||
        (z[i] > 8.05f && fabsf(z[i] - 12.0f) > 2e-3f && z[i] != NO_DEPTH))
      fail_msg("%s: pixel %d at depth %g", path_names[p], i, (double)z[i]);
  satf_image_destroy(img);
}

static void test_clusters(void **state) { check_path(*state, CLUSTERS, 1); }
static void test_ordered(void **state) { check_path(*state, ORDERED, 1); }
static void test_strands(void **state) { check_path(*state, STRANDS, 1); }
static void test_baseline(void **state) { check_path(*state, BASELINE, 1); }
static void test_sparse(void **state) { check_path(*state, SPARSE, 1); }
/* jittered samples: their median, never a mean across the hair's edges */
static void test_samples(void **state) {
  check_path(*state, CLUSTERS, 4);
  check_path(*state, STRANDS, 3);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_clusters), cmocka_unit_test(test_ordered),
      cmocka_unit_test(test_strands),  cmocka_unit_test(test_baseline),
      cmocka_unit_test(test_sparse),   cmocka_unit_test(test_samples)};
  return cmocka_run_group_tests(tests, setup, teardown);
}
