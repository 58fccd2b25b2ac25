/* test_dom_column.c - where the deep opacity map puts a cluster's hair
 * (glsl/dom_write.glsl, dom_fs.glsl): each face of its outermost shell
 * carries the alpha of the cluster's radial column, which is spread in
 * depth from the shell to the axis, so the near half fills the slabs from
 * the first hair to the axis and the far half those behind it. Added at
 * the shell instead, the near half sat in the first slab alone and a
 * light's ray entering a neighbour through its edge counted it all. */
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

#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/gl.h"
#include "satf/render.h"

#define W 64
#define H 64

FIXTURE_GL_GROUP(W, H)

/* One straight cluster of radius 1 along y, lit along -z: the map's slabs
 * are a third of its radius deep (dom.h: dom_place), so the axis lies
 * about three slabs behind the first hair at the middle of the cluster. */
static const char *const SCENE =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, -2, 0], [0, 2, 0]], \"a\": 1.0,"
    "  \"shell\": {\"layers\": 4, \"st\": 8, \"su\": 12},"
    "  \"density\": {\"strands\": 400, \"seed\": 3,"
    "               \"strand_width\": 0.05}}}],"
    " \"camera\": {\"position\": [0, 0, 9], \"target\": [0, 0, 0],"
    "            \"fov_y\": 40},"
    " \"lights\": [{\"direction\": [0, 0, -1]}],"
    " \"background\": [0, 0, 0]}";

static void test_column_spread_to_axis(void **state) {
  const fixture_gl *f = *state;
  satf_scene *s = fixture_scene(SCENE);
  assert_non_null(s);
  satf_renderer *r = fixture_renderer(s, f->db, W, H, 0);
  assert_non_null(r);
  satf_error err;
  satf_image *img = NULL;
  if (satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_true(r->dom.valid);
  int w = satf_gl_target_width(r->dom.opacity);
  int h = satf_gl_target_height(r->dom.opacity);
  float *o = malloc(4 * (size_t)w * (size_t)h * sizeof *o);
  assert_non_null(o);
  if (satf_gl_target_read_bottom_up(r->dom.opacity, 0, o,
                                    4 * (size_t)w * (size_t)h, &err) != SATF_OK)
    fail_msg("%s", err.message);
  /* the texels the middle of the cluster's width covers: the most hair */
  float most = 0.0f;
  for (size_t i = 0; i < (size_t)w * h; i++) {
    float t = o[4 * i] + o[4 * i + 1] + o[4 * i + 2] + o[4 * i + 3];
    most = t > most ? t : most;
  }
  assert_true(most > 0.0f);
  double slab[4] = {0.0, 0.0, 0.0, 0.0}, all = 0.0;
  int n = 0;
  for (size_t i = 0; i < (size_t)w * h; i++) {
    const float *p = o + 4 * i;
    if (p[0] + p[1] + p[2] + p[3] < 0.8f * most)
      continue;
    for (int k = 0; k < 4; k++) {
      slab[k] += p[k];
      all += p[k];
    }
    n++;
  }
  printf("%d texels: slabs %.3f %.3f %.3f %.3f of the hair\n", n, slab[0] / all,
         slab[1] / all, slab[2] / all, slab[3] / all);
  assert_true(n > 10);
  /* the near half over the first three slabs, the far half mostly beyond
   * them (added at the shell: 0.45, 0.00, 0.05, 0.51; spread: about 0.2
   * in each of the first three) */
  for (int k = 0; k < 3; k++) {
    assert_true(slab[k] > 0.1 * all);
    assert_true(slab[k] < 0.3 * all);
  }
  assert_true(slab[3] > 0.25 * all && slab[3] < 0.6 * all);
  free(o);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_column_spread_to_axis),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
