/* test_hair_directions.c - the physical shading of a cluster follows its
 * strands' own course (satf_sector_hair_directions, satf_shell_geom_set_hair,
 * maps_fiber.c): a twisted rope of strands crossing its trajectory is lit
 * as the same strands drawn as strands, and not as fibres along the
 * trajectory would be; the directions lie in the sectors' surfaces and
 * follow the rope when an animation bends it; a curly cluster's cone
 * stays about them. Whole
 * frames on llvmpipe through EGL, on a small fibre database. */
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

#include "maps.h"
#include "maps_fiber.h"
#include "metrics.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/common.h"
#include "satf/math.h"
#include "satf/render.h"

#define W 96
#define H 128
#define STRANDS 400
#define SLICES 9
#define WIND 2.6 /* radians each strand turns about the axis, root to tip */

FIXTURE_FIBER_GROUP(W, H)

/* A rope: one straight cluster along y (4 long, radius 1) of STRANDS
 * strands, each winding WIND radians about the axis, so a strand at
 * radius v crosses the trajectory at atan(v WIND / 4) (33 degrees at the
 * rim), seen from +z, lit from the right and front. */
static char *rope_json(void) {
  size_t cap = (size_t)STRANDS * SLICES * 2 * 16 + 2048;
  char *json = malloc(cap);
  assert_non_null(json);
  size_t at =
      (size_t)snprintf(json, cap,
                       "{\"macro_clusters\": [{\"prototype\": {"
                       "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 1,"
                       "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 16},"
                       "  \"density\": {\"type\": \"tracks\", \"slices\": %d,"
                       "    \"strand_width\": 0.06, \"tracks\": [",
                       SLICES);
  unsigned seed = 7;
  for (int k = 0; k < STRANDS; k++) {
    seed = seed * 1103515245u + 12345u;
    double v = 0.95 * sqrt((double)((seed >> 8) % 10000u) / 10000.0);
    seed = seed * 1103515245u + 12345u;
    double u0 = SATF_TWO_PI * (double)((seed >> 8) % 10000u) / 10000.0;
    at += (size_t)snprintf(json + at, cap - at, "%s[0", k ? ", " : "");
    for (int s = 0; s < SLICES; s++) {
      double u = u0 + WIND * s / (SLICES - 1);
      at += (size_t)snprintf(json + at, cap - at, ", %.5f, %.5f", v * cos(u),
                             v * sin(u));
    }
    at += (size_t)snprintf(json + at, cap - at, "]");
  }
  snprintf(json + at, cap - at,
           "]}}}],"
           " \"camera\": {\"position\": [0, 0, 9], \"target\": [0, 0, 0],"
           "              \"fov_y\": 40},"
           " \"lights\": [{\"direction\": [-1, 0, -1]}],"
           " \"material\": {\"model\": \"physical\"},"
           " \"background\": [0, 0, 0],"
           " \"image\": {\"width\": %d, \"height\": %d}}",
           W, H);
  return json;
}

enum { AS_STRANDS, FOLLOWING, ALONG_TRAJECTORY };

/* The rope drawn as its strands, as shells following them, or as shells
 * whose fibres run along the trajectory (the hair directions taken away
 * before the first frame). */
static satf_image *render(int how) {
  char *json = rope_json();
  satf_scene *s = fixture_scene(json);
  free(json);
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, fiber_db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  if (how == AS_STRANDS)
    assert_int_equal(
        satf_renderer_set_sparse_strands(r, SATF_SPARSE_STRANDS_MAX, &err),
        SATF_OK);
  /* the strands gave every column a direction */
  proto *p = &r->protos[0];
  assert_non_null(p->geom.hair);
  if (how == ALONG_TRAJECTORY) {
    free(p->geom.hair);
    p->geom.hair = NULL;
    for (int i = 0; i < p->ninsts; i++)
      r->insts[p->first_inst + i].geom.hair = NULL;
  }
  satf_image *img = fixture_render_image(r);
  assert_non_null(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
  return img;
}

static compare_result measure(const satf_image *ref, const satf_image *test,
                              const char *what) {
  compare_image a = fixture_compare_image(ref, "strands");
  compare_image b = fixture_compare_image(test, what);
  compare_result res;
  satf_error err;
  assert_int_equal(compare_measure(&a, &b, &res, &err), SATF_OK);
  printf("%s against the strands: luminance x %.3f, IoU %.3f, SSIM4 %.3f\n",
         what, res.lum_ratio, res.iou, res.ssim4);
  return res;
}

static void test_rope_lit_as_its_strands(void **state) {
  (void)state;
  satf_image *ref = render(AS_STRANDS);
  satf_image *follow = render(FOLLOWING);
  satf_image *along = render(ALONG_TRAJECTORY);
  compare_result f = measure(ref, follow, "shells following the strands");
  compare_result a = measure(ref, along, "shells along the trajectory");
  double ef = fabs(log(f.lum_ratio)), ea = fabs(log(a.lum_ratio));
  assert_true(ef < 0.5 * ea);
  assert_true(ef < log(1.15));
  assert_true(f.ssim4 > a.ssim4 + 0.2);
  satf_image_destroy(ref);
  satf_image_destroy(follow);
  satf_image_destroy(along);
}

/* A straight cluster along y (4 long, radius 1) and the sector geometry
 * of shells sh on it, into *g; the cluster, to destroy after g. */
static satf_cluster *straight_shells(const satf_shell_params *sh,
                                     satf_shell_geom *g) {
  const float traj[6] = {0, -2, 0, 0, 2, 0}, one = 1.0f, zero = 0.0f;
  satf_cluster_desc d = {2, traj, 1, &one, &one, &zero};
  satf_cluster *cl = NULL;
  satf_error err;
  assert_int_equal(satf_cluster_create(&d, &cl, &err), SATF_OK);
  assert_int_equal(satf_shell_geom_create(cl, sh, g, &err), SATF_OK);
  return cl;
}

/* satf_shell_geom_set_hair keeps what lies in each sector's surface: a
 * direction tilted towards the outward normal N loses that part (turned
 * towards the phase direction T, it stays turned), one along N or none at
 * all leaves N x T, bit for bit the direction without hair. */
static void test_hair_in_surface(void **state) {
  (void)state;
  satf_shell_params sh = {3, 4, 8, 0.2f};
  satf_shell_geom g;
  satf_cluster *cl = straight_shells(&sh, &g);
  satf_error err;
  size_t n = satf_shell_sector_count(&sh);
  float *dirs = calloc(n * 3, sizeof *dirs),
        *plain = malloc(n * 3 * sizeof *plain);
  assert_true(dirs && plain);
  for (size_t q = 0; q < n; q++) {
    maps_sector_hair(&g, q, plain + 3 * q);
    const float *N = g.frames + 9 * q + 3, *T = N + 3;
    float *v = dirs + 3 * q;
    if (q % 4 == 0) /* the trajectory's direction, tilted towards N */
      for (int c = 0; c < 3; c++)
        v[c] = plain[3 * q + c] + 0.7f * N[c];
    else if (q % 4 == 1) /* along N */
      memcpy(v, N, 3 * sizeof(float));
    else if (q % 4 == 2) /* turned 0.5 radians towards T, and towards N */
      for (int c = 0; c < 3; c++)
        v[c] = cosf(0.5f) * plain[3 * q + c] + sinf(0.5f) * T[c] + 0.4f * N[c];
  }
  unsigned long serial = g.serial;
  assert_int_equal(satf_shell_geom_set_hair(&g, dirs, &err), SATF_OK);
  assert_true(g.serial != serial);
  for (size_t q = 0; q < n; q++) {
    float h[3];
    maps_sector_hair(&g, q, h);
    const float *T = g.frames + 9 * q + 6;
    if (q % 4 == 0) {
      for (int c = 0; c < 3; c++)
        assert_true(fabsf(h[c] - plain[3 * q + c]) < 1e-5f);
    } else if (q % 4 == 2) {
      for (int c = 0; c < 3; c++)
        assert_true(fabsf(h[c] - (cosf(0.5f) * plain[3 * q + c] +
                                  sinf(0.5f) * T[c])) < 1e-5f);
    } else
      assert_memory_equal(h, plain + 3 * q, sizeof h);
  }
  free(dirs);
  free(plain);
  satf_shell_geom_destroy(&g);
  satf_cluster_destroy(cl);
}

/* A rope that bends (an animation's next scene, satf_renderer_set_scene)
 * gets the directions of its new course: bit for bit those a renderer
 * made for the bent scene finds, and not the straight rope's. */
static void test_bent_rope_follows(void **state) {
  (void)state;
  char *json = rope_json();
  satf_scene *s = fixture_scene(json), *bent = fixture_scene(json);
  free(json);
  assert_true(s && bent);
  satf_scene_cluster *c = &bent->macro_clusters[0].prototype;
  c->trajectory[3 * (c->n_points - 1)] += 1.5f; /* the tip swings in x */
  satf_renderer *r = fixture_renderer(s, fiber_db, W, H, 2);
  satf_renderer *fresh = fixture_renderer(bent, fiber_db, W, H, 2);
  assert_true(r && fresh);
  size_t n = satf_shell_sector_count(&r->protos[0].geom.shell);
  float *before = malloc(n * 3 * sizeof *before);
  assert_non_null(before);
  memcpy(before, r->protos[0].geom.hair, n * 3 * sizeof *before);
  satf_error err;
  int rebuilt = 0;
  assert_int_equal(satf_renderer_set_scene(r, bent, &rebuilt, &err), SATF_OK);
  assert_int_equal(rebuilt, 1);
  const satf_shell_geom *g = &r->protos[0].geom, *want = &fresh->protos[0].geom;
  assert_non_null(g->hair);
  assert_memory_equal(g->hair, want->hair, n * 3 * sizeof(float));
  assert_memory_not_equal(g->hair, before, n * 3 * sizeof(float));
  /* the instances' copies of the geometry take the new directions */
  assert_ptr_equal(r->insts[r->protos[0].first_inst].geom.hair, g->hair);
  free(before);
  satf_renderer_destroy(r);
  satf_renderer_destroy(fresh);
  satf_scene_destroy(bent);
  satf_scene_destroy(s);
}

/* A curly cluster's cone (maps_cone_tangents) about a hair the strands
 * turned within the surface: every tangent a unit vector at the curl's
 * angle to that hair, around it evenly (their mean along it). Built on
 * the sector's phase direction T as for the hair N x T, the tangents of
 * a hair turned 0.6 radians are not (lengths 0.8-1.2). */
static void test_cone_about_own_hair(void **state) {
  (void)state;
  satf_shell_params sh = {2, 3, 6, 0.2f};
  satf_shell_geom g;
  satf_cluster *cl = straight_shells(&sh, &g);
  satf_error err;
  size_t n = satf_shell_sector_count(&sh);
  float *dirs = malloc(n * 3 * sizeof *dirs);
  assert_non_null(dirs);
  for (size_t q = 0; q < n; q++) {
    const float *T = g.frames + 9 * q + 6;
    float h[3];
    maps_sector_hair(&g, q, h);
    for (int c = 0; c < 3; c++)
      dirs[3 * q + c] = cosf(0.6f) * h[c] + sinf(0.6f) * T[c];
  }
  assert_int_equal(satf_shell_geom_set_hair(&g, dirs, &err), SATF_OK);
  const float tilt = 0.5f;
  double worst_old = 0.0;
  for (size_t q = 0; q < n; q++) {
    float h[3], t[TILT_TANGENTS][3], old[TILT_TANGENTS][3];
    maps_sector_hair(&g, q, h);
    maps_cone_tangents(h, g.frames + 9 * q, 1, tilt, t);
    maps_cone_tangents(h, g.frames + 9 * q, 0, tilt, old);
    float mean[3] = {0, 0, 0};
    for (int k = 0; k < TILT_TANGENTS; k++) {
      float len =
          sqrtf(t[k][0] * t[k][0] + t[k][1] * t[k][1] + t[k][2] * t[k][2]);
      assert_true(fabsf(len - 1.0f) < 1e-5f);
      assert_true(fabsf(t[k][0] * h[0] + t[k][1] * h[1] + t[k][2] * h[2] -
                        cosf(tilt)) < 1e-5f);
      for (int c = 0; c < 3; c++)
        mean[c] += t[k][c] / TILT_TANGENTS;
      double lo = sqrt(old[k][0] * old[k][0] + old[k][1] * old[k][1] +
                       old[k][2] * old[k][2]);
      worst_old = fmax(worst_old, fabs(lo - 1.0));
    }
    for (int c = 0; c < 3; c++)
      assert_true(fabsf(mean[c] - cosf(tilt) * h[c]) < 1e-5f);
  }
  printf("cone on T about a hair turned 0.6 rad: tangent lengths off by up "
         "to %.3f\n",
         worst_old);
  assert_true(worst_old > 0.05);
  free(dirs);
  satf_shell_geom_destroy(&g);
  satf_cluster_destroy(cl);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rope_lit_as_its_strands),
      cmocka_unit_test(test_hair_in_surface),
      cmocka_unit_test(test_bent_rope_follows),
      cmocka_unit_test(test_cone_about_own_hair),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
