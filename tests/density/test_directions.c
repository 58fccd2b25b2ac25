/* test_directions.c - where a cluster's own strands run in each boundary
 * sector (satf_sector_hair_directions, online/density/directions.c): a
 * strand winding about a straight cluster's axis gives its chord's
 * direction, worked out by hand; one along the axis gives the axis; a
 * short strand counts only where it spans the sector's t; a column takes
 * the strands of the two beside it; every layer of a column the same;
 * empty columns zero; and densities without tracks are refused. */
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

#include "satf/density.h"
#include "satf/geometry.h"
#include "satf/scene.h"

#define SU 8
#define ST 4
#define LAYERS 3
#define TURN 0.1 /* radians strand 0 turns about the axis per slice */

/* A straight cluster along +y, 4 long, radius 1, tracks over 5 slices
 * (t = 0, 0.25 ... 1, so y = 0, 1 ... 4): strand 0 at v = 0.8 winding from
 * phase 0 by TURN a slice; strand 1 at phase pi, v = 0.5, along the axis;
 * strand 2 at phase pi / 2, v = 0.6, on slices 1 and 2 only. */
static satf_scene *scene(void) {
  char json[2048];
  int at = snprintf(json, sizeof json,
                    "{\"macro_clusters\": [{\"prototype\": {"
                    "  \"trajectory\": [[0, 0, 0], [0, 4, 0]], \"a\": 1,"
                    "  \"density\": {\"type\": \"tracks\", \"slices\": 5,"
                    "    \"strand_width\": 0.05, \"tracks\": [[0");
  for (int s = 0; s < 5; s++)
    at += snprintf(json + at, sizeof json - (size_t)at, ", %.9f, %.9f",
                   0.8 * cos(TURN * s), 0.8 * sin(TURN * s));
  snprintf(json + at, sizeof json - (size_t)at,
           "], [0, -0.5, 0, -0.5, 0, -0.5, 0, -0.5, 0, -0.5, 0],"
           " [1, 0, 0.6, 0, 0.6]]}}}]}");
  satf_scene *s = NULL;
  satf_error err;
  if (satf_scene_parse(json, strlen(json), "t.json", &s, &err) != SATF_OK)
    fail_msg("%s", err.message);
  return s;
}

static satf_cluster *cluster(const satf_scene_cluster *c) {
  float radii[3] = {c->a.values[0], c->b.values[0], 0.0f};
  satf_cluster_desc d = {c->n_points, c->trajectory, 1,
                         radii,       radii + 1,     radii + 2};
  satf_cluster *out = NULL;
  satf_error err;
  if (satf_cluster_create(&d, &out, &err) != SATF_OK)
    fail_msg("%s", err.message);
  return out;
}

static const float *at(const float *dirs, int i, int k, int j) {
  return dirs + 3 * (((size_t)i * LAYERS + (size_t)k) * SU + (size_t)j);
}

static int is_zero(const float *d) {
  return d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f;
}

static void test_directions(void **state) {
  (void)state;
  satf_scene *s = scene();
  const satf_scene_cluster *c = &s->macro_clusters[0].prototype;
  satf_cluster *cl = cluster(c);
  satf_shell_params sh = {LAYERS, ST, SU, 0.2f};
  float *dirs = malloc((ST + 1) * LAYERS * SU * 3 * sizeof *dirs);
  assert_non_null(dirs);
  satf_error err;
  assert_int_equal(
      satf_sector_hair_directions(cl, &sh, &c->density, 2, dirs, &err),
      SATF_OK);
  /* strand 0's chord between slices: 1 along the axis, 2 v sin(TURN / 2)
   * across it, so its cosine to the axis is 1 / sqrt(1 + that^2) */
  double across = 2.0 * 0.8 * sin(TURN / 2.0);
  double cos0 = 1.0 / sqrt(1.0 + across * across);
  for (int i = 0; i <= ST; i++) {
    for (int k = 0; k < LAYERS; k++)
      for (int j = 0; j < SU; j++)
        assert_memory_equal(at(dirs, i, k, j), at(dirs, i, 0, j),
                            3 * sizeof(float));
    /* phase column 0 holds strand 0 alone (at phases 0 to 0.4; columns
     * are pi / 4 wide), column 4 strand 1 (phase pi) */
    const float *d0 = at(dirs, i, 0, 0), *d4 = at(dirs, i, 0, 4);
    printf("t %.2f: column 0 (%.5f %.5f %.5f), cosine to the axis %.6f "
           "(by hand %.6f)\n",
           (double)i / ST, (double)d0[0], (double)d0[1], (double)d0[2],
           (double)d0[1], cos0);
    assert_true(fabs(d0[1] - cos0) < 1e-5);
    assert_true(
        fabs(sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]) - 1.0) < 1e-5);
    assert_true(fabs(d4[1] - 1.0) < 1e-6);
    /* the columns beside take their neighbours' strands */
    assert_memory_equal(at(dirs, i, 0, 7), d0, 3 * sizeof(float));
    assert_memory_equal(at(dirs, i, 0, 3), d4, 3 * sizeof(float));
    assert_memory_equal(at(dirs, i, 0, 5), d4, 3 * sizeof(float));
    /* no strand within a column of column 6 */
    assert_true(is_zero(at(dirs, i, 0, 6)));
  }
  /* strand 2 spans t = 0.25 .. 0.5 only: at t = 0.25 column 2 is its (the
   * axis), and column 1 the mean of it and strand 0 */
  assert_true(fabs(at(dirs, 1, 0, 2)[1] - 1.0) < 1e-6);
  const float *d0 = at(dirs, 1, 0, 0), *d1 = at(dirs, 1, 0, 1);
  float m[3] = {d0[0], d0[1] + 1.0f, d0[2]};
  float len = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  for (int q = 0; q < 3; q++)
    assert_true(fabsf(d1[q] - m[q] / len) < 1e-5);
  for (int i = 0; i <= ST; i++)
    if (i != 1)
      assert_true(is_zero(at(dirs, i, 0, 2)));
  free(dirs);
  satf_cluster_destroy(cl);
  satf_scene_destroy(s);
}

/* A procedural density has no strands of its own to follow. */
static void test_needs_tracks(void **state) {
  (void)state;
  satf_scene *s = scene();
  satf_scene_cluster *c = &s->macro_clusters[0].prototype;
  satf_cluster *cl = cluster(c);
  satf_shell_params sh = {LAYERS, ST, SU, 0.2f};
  float dirs[(ST + 1) * LAYERS * SU * 3];
  satf_scene_density procedural = c->density;
  procedural.type = SATF_SCENE_DENSITY_PROCEDURAL;
  satf_error err;
  assert_int_equal(
      satf_sector_hair_directions(cl, &sh, &procedural, 1, dirs, &err),
      SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "tracks"));
  satf_shell_params bad = {0, ST, SU, 0.2f};
  assert_int_not_equal(
      satf_sector_hair_directions(cl, &bad, &c->density, 1, dirs, &err),
      SATF_OK);
  satf_cluster_destroy(cl);
  satf_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_directions),
      cmocka_unit_test(test_needs_tracks),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
