/* test_dom_cheap.c - cluster shadows of moving hair:
 * the deep opacity map kept across scene changes while no cluster moved
 * more than the tolerance (texels across the light, slabs along it), the
 * move measured from where the map was drawn, and drawn again beyond it
 * with the image of a fresh renderer bit for bit; and the off switch, the
 * exact rule: drawn again after every scene change. */
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
#include "renderer_internal.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "test_util.h"

#define W 96
#define H 72

FIXTURE_GL_GROUP(W, H)

/* Five clusters, three of them behind others from the light: in their
 * shadow. */
static const char *const SCENE =
    "{\"macro_clusters\": ["
    " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.2, -0.5, 0],"
    "   [0.2, 0.8, 0.1], [0, 2, 0]], \"a\": 0.5,"
    "   \"shell\": {\"layers\": 3, \"st\": 8, \"su\": 6},"
    "   \"density\": {\"strands\": 90, \"seed\": 7}},"
    "  \"instances\": ["
    "   {\"translate\": [-1.2, 0, 0]},"
    "   {\"translate\": [0, 0, 0.3]},"
    "   {\"translate\": [-0.75, -0.4, -0.6]},"
    "   {\"translate\": [1.0, 0, -0.2]},"
    "   {\"translate\": [0.3, -0.2, -1.2]}]}],"
    " \"camera\": {\"position\": [0, 1, 14], \"target\": [0, 0, 0],"
    "            \"fov_y\": 30},"
    " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"
    " \"background\": [0, 0, 0]}";

/* tol: satf_renderer_set_shadow_move's texels (negative: the exact rule) */
static satf_renderer *make(const fixture_gl *f, const satf_scene *scene,
                           float tol) {
  satf_renderer *r = fixture_renderer(scene, f->db, W, H, 2);
  if (r)
    satf_renderer_set_shadow_move(r, tol);
  return r;
}

static int same_image(const satf_image *a, const satf_image *b) {
  const char *ch[] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; c++)
    if (!fixture_same_bits(a, b, ch[c]))
      return 0;
  return 1;
}

/* Mean |R difference| over the frame. */
static double mean_diff(const satf_image *a, const satf_image *b) {
  const float *pa = fixture_plane(a, "R"), *pb = fixture_plane(b, "R");
  double sum = 0.0;
  for (int i = 0; pa && pb && i < W * H; i++)
    sum += fabs((double)pa[i] - (double)pb[i]);
  return sum / (W * H);
}

/* World length of one unit along row `row` of the map's light view, in
 * that row's units (texels for x, slabs for z) per world unit, and the
 * row's direction. */
static float light_axis(const satf_renderer *r, int row, float dir[3]) {
  const float *m = r->dom.drawn_viewproj + 4 * row;
  float len = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  for (int k = 0; k < 3; k++)
    dir[k] = m[k] / len;
  return row == 0 ? len * 0.5f * (float)DOM_SIZE
                  : len * 0.5f / r->dom.drawn_slab;
}

/* The scene with instance 0 moved by `units` of the map's row `row`. */
static satf_scene *moved(const satf_renderer *r, int row, float units) {
  satf_scene *s = fixture_scene(SCENE);
  if (!s)
    return NULL;
  float dir[3], per_world = light_axis(r, row, dir);
  float *m = s->macro_clusters[0].instances[0].m;
  for (int k = 0; k < 3; k++)
    m[4 * k + 3] += units / per_world * dir[k];
  return s;
}

/* Still hair: a scene change that moved nothing keeps the map (the
 * default tolerance), and the frame is the same bit for bit. */
static void test_still_hair_keeps_map(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE), *again = fixture_scene(SCENE);
  assert_non_null(scene);
  assert_non_null(again);
  satf_renderer *r = fixture_renderer(scene, f->db, W, H, 2);
  assert_non_null(r);
  satf_error err;
  assert_true(satf_renderer_shadow_move(r) == DOM_MOVE_TOL);
  satf_image *a = fixture_render_image(r);
  assert_non_null(a);
  assert_int_equal(r->dom.reuses, 0);
  assert_int_equal(satf_renderer_set_scene(r, again, NULL, &err), SATF_OK);
  assert_true(cluster_dom_hair_move(r) == 0.0f);
  satf_image *b = fixture_render_image(r);
  assert_int_equal(r->dom.reuses, 1);
  assert_true(same_image(a, b));
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_renderer_destroy(r);
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
}

/* A cluster moved across the light (row 0: texels) or along it (row 2:
 * slabs): within the tolerance the map is kept, beyond it drawn again,
 * and then the frame is a fresh renderer's bit for bit. */
static void moves(fixture_gl *f, int row) {
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  float tol = 0.5f;
  satf_renderer *r = make(f, scene, tol);
  assert_non_null(r);
  satf_image_destroy(fixture_render_image(r));
  satf_scene *near = moved(r, row, 0.6f * tol);
  satf_scene *far = moved(r, row, 1.6f * tol);
  assert_non_null(near);
  assert_non_null(far);
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, near, NULL, &err), SATF_OK);
  float m = cluster_dom_hair_move(r);
  printf("row %d: moved %.4f (tolerance %.2f)\n", row, m, tol);
  assert_float_equal(m, 0.6f * tol, 0.02f * tol);
  satf_image_destroy(fixture_render_image(r));
  assert_int_equal(r->dom.reuses, 1);
  /* the frame's shadows differ from those of the map drawn for it (the
   * move is one the test can see), by less than the cluster shadows */
  satf_renderer *now = make(f, near, tol);
  assert_non_null(now);
  satf_image *kept = fixture_render_image(r),
             *drawn = fixture_render_image(now);
  assert_int_equal(r->dom.reuses, 2);
  now->effects.cluster_shadows = 0;
  satf_image *none = fixture_render_image(now);
  double effect = mean_diff(drawn, none), err_kept = mean_diff(drawn, kept);
  printf("kept map: mean |dR| %.6f, cluster shadows' %.6f\n", err_kept, effect);
  assert_true(err_kept > 0.0);
  assert_true(err_kept < 0.1 * effect);
  satf_image_destroy(kept);
  satf_image_destroy(drawn);
  satf_image_destroy(none);
  satf_renderer_destroy(now);
  /* measured from where the map was drawn, not from the last frame */
  assert_int_equal(satf_renderer_set_scene(r, far, NULL, &err), SATF_OK);
  assert_float_equal(cluster_dom_hair_move(r), 1.6f * tol, 0.02f * tol);
  satf_image *a = fixture_render_image(r);
  assert_int_equal(r->dom.reuses, 2);
  satf_renderer *fresh = make(f, far, tol);
  assert_non_null(fresh);
  satf_image *b = fixture_render_image(fresh);
  assert_non_null(a);
  assert_non_null(b);
  assert_true(same_image(a, b));
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_renderer_destroy(fresh);
  satf_renderer_destroy(r);
  satf_scene_destroy(near);
  satf_scene_destroy(far);
  satf_scene_destroy(scene);
}

static void test_move_across_light(void **state) { moves(*state, 0); }
static void test_move_along_light(void **state) { moves(*state, 2); }

/* The key light turns: drawn again, however still the hair. */
static void test_light_turn_draws(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene, DOM_MOVE_TOL);
  assert_non_null(r);
  satf_image_destroy(fixture_render_image(r));
  satf_image_destroy(fixture_render_image(r));
  assert_int_equal(r->dom.reuses, 1);
  satf_renderer_light(r, 0)->direction[0] += 0.01f;
  satf_image_destroy(fixture_render_image(r));
  assert_int_equal(r->dom.reuses, 1);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* The off switch, the exact rule: drawn again after a scene change that
 * moved nothing, the frame the same bit for bit; and where a tolerance
 * keeps a moved cluster's map, switching it off draws the map again, the
 * frame then a fresh renderer's. */
static void test_off_switch_exact(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE), *again = fixture_scene(SCENE);
  assert_non_null(scene);
  assert_non_null(again);
  satf_renderer *r = make(f, scene, -1.0f);
  assert_non_null(r);
  assert_true(satf_renderer_shadow_move(r) < 0.0f);
  satf_image *a = fixture_render_image(r);
  satf_image_destroy(fixture_render_image(r)); /* nothing changed: kept */
  assert_int_equal(r->dom.reuses, 1);
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, again, NULL, &err), SATF_OK);
  satf_image *b = fixture_render_image(r);
  assert_int_equal(r->dom.reuses, 1);
  assert_true(same_image(a, b));
  /* a move of 0.6 texels: kept with 1, drawn again once switched off */
  satf_renderer_set_shadow_move(r, 1.0f);
  satf_scene *near = moved(r, 0, 0.6f);
  assert_non_null(near);
  assert_int_equal(satf_renderer_set_scene(r, near, NULL, &err), SATF_OK);
  satf_image *c = fixture_render_image(r);
  assert_int_equal(r->dom.reuses, 2);
  assert_int_equal(satf_renderer_set_scene(r, near, NULL, &err), SATF_OK);
  satf_renderer_set_shadow_move(r, -1.0f);
  satf_image *d = fixture_render_image(r);
  assert_int_equal(r->dom.reuses, 2);
  satf_renderer *fresh = make(f, near, -1.0f);
  assert_non_null(fresh);
  satf_image *e = fixture_render_image(fresh);
  assert_true(same_image(d, e));
  assert_false(same_image(c, e));
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(c);
  satf_image_destroy(d);
  satf_image_destroy(e);
  satf_renderer_destroy(fresh);
  satf_renderer_destroy(r);
  satf_scene_destroy(near);
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_still_hair_keeps_map),
      cmocka_unit_test(test_move_across_light),
      cmocka_unit_test(test_move_along_light),
      cmocka_unit_test(test_light_turn_draws),
      cmocka_unit_test(test_off_switch_exact),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
