/* test_perf_paths.c - the renderer's shortcuts give what the long way
 * gives: instanced draws (one call per run of a macro-cluster's
 * instances) the same image, bit for bit, as one draw per instance, in
 * both compositing modes and with mirrored instances; incremental look-ups
 * (only HSVs whose azimuths changed) the same maps as looking every HSV up
 * again, none when nothing moved and only the moved instance's when one
 * moves; prototypes of one map size in one texture array; the deep opacity map
 * reused only while its inputs stay (the light, the hair; the eye within a
 * tolerance), with the image of a fresh one or close to it. */
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

#include "bench_turn.h"
#include "render_fixture.h"
#include "renderer_internal.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "test_util.h"

#define W 96
#define H 72

FIXTURE_GL_GROUP(W, H)

/* One macro-cluster of six instances around the origin (one mirrored,
 * rotated ones) and a second prototype of two, with cluster shadows on. */
static const char *const SCENE =
    "{\"macro_clusters\": ["
    " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.3, 0, 0], [0, 2, 0]],"
    "   \"a\": 0.5, \"shell\": {\"layers\": 3, \"st\": 6, \"su\": 6},"
    "   \"density\": {\"strands\": 80, \"seed\": 3}},"
    "  \"instances\": ["
    "   {\"translate\": [-2.4, 0, 0]},"
    "   {\"translate\": [-1.2, 0, -0.5],"
    "    \"rotate\": {\"axis\": [0, 1, 0], \"angle\": 40}},"
    "   {\"translate\": [0, 0, 0.3], \"scale\": [-1, 1, 1]},"
    "   {\"translate\": [1.2, 0.2, 0],"
    "    \"rotate\": {\"axis\": [0, 0, 1], \"angle\": 15}},"
    "   {\"translate\": [2.4, 0, -0.4], \"scale\": 0.8},"
    "   {\"translate\": [0.6, -0.3, -1.5],"
    "    \"rotate\": {\"axis\": [1, 0, 0], \"angle\": 70}}]},"
    " {\"prototype\": {\"trajectory\": [[0, -1.5, 0], [0, 1.5, 0]],"
    "   \"a\": 0.4, \"shell\": {\"layers\": 2, \"st\": 4, \"su\": 8},"
    "   \"density\": {\"strands\": 60, \"seed\": 5}},"
    "  \"instances\": [{\"translate\": [-0.6, 0, 1]},"
    "                  {\"translate\": [0.6, 0, 1]}]}],"
    " \"camera\": {\"position\": [0, 1, 14], \"target\": [0, 0, 0],"
    "            \"fov_y\": 35},"
    " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"
    " \"background\": [0, 0, 0]}";

static satf_renderer *make(const fixture_gl *f, const satf_scene *scene) {
  return fixture_renderer_cpu_maps(scene, f->db, W, H, 2);
}

static satf_image *image(satf_renderer *r) { return fixture_render_image(r); }

/* Covered pixels of an image (alpha above 1/256). */
static long covered(const satf_image *img) {
  const float *a = fixture_plane(img, "A");
  long n = 0;
  for (int i = 0; a && i < W * H; i++)
    n += a[i] > 1.0f / 256.0f;
  return n;
}

/* Two frames (destroyed here) the same bit for bit, every cluster drawn:
 * a good part of the frame is hair. */
static void assert_same_frame(satf_image *a, satf_image *b) {
  assert_non_null(a);
  assert_non_null(b);
  assert_true(covered(a) > W * H / 10);
  const char *ch[] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; c++)
    assert_true(fixture_same_bits(a, b, ch[c]));
  satf_image_destroy(a);
  satf_image_destroy(b);
}

static void test_instanced_same_image(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene);
  assert_non_null(r);
  /* the runs: the mirrored instance splits the first prototype's */
  assert_int_equal(r->protos[0].ninsts, 6);
  assert_int_equal(r->insts[2].mirrored, 1);
  assert_int_equal(r->insts[3].layer0, 3 * 3);
  assert_true(r->insts[0].tex == r->insts[5].tex);
  for (int mode = 0; mode < 2; mode++) {
    satf_renderer_set_composite(r, mode ? SATF_COMPOSITE_ORDERED
                                        : SATF_COMPOSITE_EXACT);
    r->instanced = 1;
    satf_image *a = image(r);
    r->instanced = 0;
    assert_same_frame(a, image(r));
  }
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* Three prototypes in three macro-clusters: the first and the last of one
 * map size (su 6; st 5 and 7 both take 8 rows of HSVs), the middle one of
 * another, so that the list's order changes array twice. */
static const char *const SHARED =
    "{\"macro_clusters\": ["
    " {\"prototype\": {\"trajectory\": [[0, -2, 0], [0.3, 0, 0], [0, 2, 0]],"
    "   \"a\": 0.5, \"shell\": {\"layers\": 3, \"st\": 5, \"su\": 6},"
    "   \"density\": {\"strands\": 80, \"seed\": 3}},"
    "  \"instances\": [{\"translate\": [-1.5, 0, 0]},"
    "                  {\"translate\": [1.5, 0, 0]}]},"
    " {\"prototype\": {\"trajectory\": [[0, -1.5, 0], [0, 1.5, 0]],"
    "   \"a\": 0.4, \"shell\": {\"layers\": 2, \"st\": 4, \"su\": 8},"
    "   \"density\": {\"strands\": 60, \"seed\": 5}},"
    "  \"instances\": [{\"translate\": [0, 0, -1]}]},"
    " {\"prototype\": {"
    "   \"trajectory\": [[0, -1.8, 0], [-0.4, 0, 0], [0, 1.8, 0]],"
    "   \"a\": 0.45, \"shell\": {\"layers\": 2, \"st\": 7, \"su\": 6},"
    "   \"density\": {\"strands\": 70, \"seed\": 4}},"
    "  \"instances\": [{\"translate\": [0, 0, 0.5]}]}],"
    " \"camera\": {\"position\": [0, 1, 14], \"target\": [0, 0, 0],"
    "            \"fov_y\": 35},"
    " \"lights\": [{\"direction\": [-0.5, -0.6, -0.6]}],"
    " \"background\": [0, 0, 0]}";

/* Prototypes of one map size share a texture array, each instance in
 * layers of its own; the shading pass draws array by array, binding each
 * once (the list's order would bind three times), with the image of one
 * draw per instance in list order. */
static void test_shared_map_arrays(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SHARED);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene);
  assert_non_null(r);
  assert_int_equal(r->ninsts, 4);
  assert_int_equal(r->n_map_arrays, 2);
  /* the first and last prototypes' three instances in one array, one
   * after another (3, 3 and 2 layers), the middle prototype's apart */
  const inst *in = r->insts;
  assert_true(in[0].tex == in[1].tex && in[1].tex == in[3].tex);
  assert_true(in[2].tex != in[0].tex);
  int layers[3] = {in[0].layer0, in[1].layer0, in[3].layer0};
  for (int a = 0; a < 3; a++)
    for (int b = a + 1; b < 3; b++)
      assert_true(layers[a] != layers[b]);
  assert_int_equal(layers[0] + layers[1] + layers[2], 0 + 3 + 6);
  assert_int_equal(in[2].layer0, 0);
  r->instanced = 1;
  satf_image *a = image(r);
  assert_int_equal(r->map_binds, 2);
  r->instanced = 0;
  satf_image *b = image(r);
  assert_int_equal(r->map_binds, 3);
  assert_same_frame(a, b);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

/* Every instance's texels (half floats), copied. */
static uint16_t *all_texels(const satf_renderer *r, size_t *count) {
  size_t n = 0;
  for (int i = 0; i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    n += satf_maps_layer_texels(&in->geom, r->w) * 4 *
         (size_t)(in->geom.shell.layers * r->quads);
  }
  uint16_t *out = malloc(n * sizeof *out), *p = out;
  for (int i = 0; out && i < r->ninsts; i++) {
    const inst *in = &r->insts[i];
    size_t k = satf_maps_layer_texels(&in->geom, r->w) * 4 *
               (size_t)(in->geom.shell.layers * r->quads);
    memcpy(p, in->texels, k * sizeof *p);
    p += k;
  }
  *count = n;
  return out;
}

/* The two renderers' maps are the same, bit for bit. */
static void assert_same_maps(const satf_renderer *r,
                             const satf_renderer *full) {
  size_t na, nb;
  uint16_t *a = all_texels(r, &na), *b = all_texels(full, &nb);
  assert_non_null(a);
  assert_non_null(b);
  assert_int_equal(na, nb);
  assert_memory_equal(a, b, na * sizeof *a);
  free(a);
  free(b);
}

static void test_incremental_lookups(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene), *full = make(f, scene);
  assert_non_null(r);
  assert_non_null(full);
  full->incremental = 0;
  long first = fixture_render_lookups(r);
  assert_true(first > 0);
  assert_int_equal(fixture_render_lookups(full), first);
  /* nothing moved: nothing looked up, nothing uploaded */
  assert_int_equal(fixture_render_lookups(r), 0);
  assert_int_equal(r->maps_changed, 0);
  /* the camera turns a little: every view azimuth changes, and the maps
   * equal a full look-up's */
  satf_scene_camera *cams[2] = {satf_renderer_camera(r),
                                satf_renderer_camera(full)};
  for (int c = 0; c < 2; c++)
    cams[c]->position[0] += 0.7f;
  long moved = fixture_render_lookups(r);
  assert_int_equal(moved, fixture_render_lookups(full));
  assert_same_maps(r, full);
  /* one instance moves: only its HSVs are looked up again */
  satf_scene *next = fixture_scene(SCENE);
  assert_non_null(next);
  next->macro_clusters[1].instances[1].m[3] += 0.25f; /* x translation */
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, next, NULL, &err), SATF_OK);
  assert_int_equal(satf_renderer_set_scene(full, next, NULL, &err), SATF_OK);
  for (int c = 0; c < 2; c++) /* set_scene takes the scene's camera */
    cams[c]->position[0] += 0.7f;
  long one = fixture_render_lookups(r);
  long all = fixture_render_lookups(full);
  assert_true(one > 0);
  assert_true(one < all / 4);
  assert_int_equal(r->maps_changed, 1);
  assert_same_maps(r, full);
  satf_renderer_destroy(r);
  satf_renderer_destroy(full);
  satf_scene_destroy(next);
  satf_scene_destroy(scene);
}

/* One instance moved, on two threads: its layers are looked up on both
 * (frame.c, build_maps_by_layer), and its maps and the frame equal those
 * of one thread, which builds the instance whole, bit for bit. */
static void test_layers_split(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE), *next = fixture_scene(SCENE);
  assert_non_null(scene);
  assert_non_null(next);
  satf_renderer *two = fixture_renderer_cpu_maps(scene, f->db, W, H, 2);
  satf_renderer *one = fixture_renderer_cpu_maps(scene, f->db, W, H, 1);
  assert_non_null(two);
  assert_non_null(one);
  assert_int_equal(fixture_render_lookups(two), fixture_render_lookups(one));
  next->macro_clusters[0].instances[3].m[7] += 0.2f; /* y translation */
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(two, next, NULL, &err), SATF_OK);
  assert_int_equal(satf_renderer_set_scene(one, next, NULL, &err), SATF_OK);
  long a = fixture_render_lookups(two);
  assert_true(a > 0);
  assert_int_equal(a, fixture_render_lookups(one));
  assert_int_equal(two->maps_changed, 1);
  assert_same_maps(two, one);
  satf_image *x = image(two);
  assert_same_frame(x, image(one));
  satf_renderer_destroy(two);
  satf_renderer_destroy(one);
  satf_scene_destroy(next);
  satf_scene_destroy(scene);
}

/* Mean |difference| of channel R between two frames of W x H. */
static double mean_diff(const satf_image *a, const satf_image *b) {
  const float *pa = fixture_plane(a, "R"), *pb = fixture_plane(b, "R");
  double sum = 0.0;
  for (int i = 0; pa && pb && i < W * H; i++)
    sum += fabs((double)pa[i] - (double)pb[i]);
  return sum / (W * H);
}

/* What the cluster shadows change in r's next frame at its camera. */
static double shadow_effect(satf_renderer *r, const satf_image *with) {
  r->effects.cluster_shadows = 0;
  satf_image *none = image(r);
  r->effects.cluster_shadows = 1;
  double d = mean_diff(with, none);
  satf_image_destroy(none);
  return d;
}

static void test_dom_reuse(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene);
  assert_non_null(r);
  satf_image *a = image(r);
  assert_int_equal(r->dom.reuses, 0);
  /* the same view again: the map is kept, and the frame is the same */
  satf_image *b = image(r);
  assert_int_equal(r->dom.reuses, 1);
  assert_true(fixture_same_bits(a, b, "R"));
  assert_true(fixture_same_bits(a, b, "A"));
  /* the camera moves: the maps' alpha changes with the eye's azimuth,
   * but the map stands for the light's view and is kept; the frame is
   * close to that of a fresh renderer, whose map is made for this eye */
  satf_renderer_camera(r)->position[0] += 3.0f;
  satf_image *c = image(r);
  assert_int_equal(r->dom.reuses, 2);
  assert_true(r->maps_changed > 0);
  satf_renderer *fresh = make(f, scene);
  assert_non_null(fresh);
  satf_renderer_camera(fresh)->position[0] += 3.0f;
  satf_image *d = image(fresh);
  assert_non_null(c);
  assert_non_null(d);
  double effect = shadow_effect(fresh, d), kept = mean_diff(c, d);
  printf("kept map: mean |dR| %.6f, cluster shadows' %.6f\n", kept, effect);
  assert_true(effect > 1e-3);
  assert_true(kept < 0.1 * effect);
  /* with no tolerance for the eye, the map is drawn again, and the frame
   * equals the fresh renderer's bit for bit */
  r->dom.eye_tol = 0.0f;
  satf_image *e = image(r);
  assert_int_equal(r->dom.reuses, 2);
  assert_true(fixture_same_bits(e, d, "R"));
  assert_true(fixture_same_bits(e, d, "A"));
  /* a tolerance: kept while the eye has turned less, drawn beyond */
  r->dom.eye_tol = 10.0f * SATF_PI_F / 180.0f;
  bench_turn(satf_renderer_camera(r), 5.0f * SATF_PI_F / 180.0f);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  bench_turn(satf_renderer_camera(r), 10.0f * SATF_PI_F / 180.0f);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  /* the key light turns: drawn again, however far the eye may turn */
  r->dom.eye_tol = INFINITY;
  satf_renderer_light(r, 0)->direction[0] += 0.3f;
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 4);
  /* a new state of the scene: drawn again under the exact rule (the
   * default measures how far the hair moved: test_dom_cheap) */
  satf_renderer_set_shadow_move(r, -1.0f);
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, scene, NULL, &err), SATF_OK);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 4);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(c);
  satf_image_destroy(d);
  satf_image_destroy(e);
  satf_renderer_destroy(r);
  satf_renderer_destroy(fresh);
  satf_scene_destroy(scene);
}

/* Strands in a row along the light's way, for the strand path: each one
 * shadows the next. */
static void set_row_of_strands(satf_renderer *r) {
  enum { N = 6, P = 5 };
  int counts[N];
  float xyz[N * P * 3];
  for (int i = 0, at = 0; i < N; i++) {
    counts[i] = P;
    for (int j = 0; j < P; j++, at++) {
      xyz[3 * at] = -1.0f + 0.4f * (float)i; /* the light's way in xz */
      xyz[3 * at + 1] = -2.0f + 4.0f * (float)j / (P - 1);
      xyz[3 * at + 2] = -1.0f + 0.48f * (float)i;
    }
  }
  satf_error err;
  assert_int_equal(
      satf_renderer_set_strands(r, N, counts, xyz, NULL, 0.15f, &err), SATF_OK);
}

/* A frame of r within a hair's breadth of a fresh renderer's for the
 * same scene, camera and light (its map drawn for this frame). */
static void assert_like_fresh(fixture_gl *f, const satf_scene *scene,
                              satf_renderer *r, satf_image *img) {
  satf_renderer *fresh = make(f, scene);
  assert_non_null(fresh);
  set_row_of_strands(fresh);
  *satf_renderer_camera(fresh) = *satf_renderer_camera(r);
  *satf_renderer_light(fresh, 0) = *satf_renderer_light(r, 0);
  satf_image *want = image(fresh);
  double most = fixture_max_diff(img, want, "R");
  printf("strand path against a fresh renderer: max |dR| %.2g\n", most);
  assert_true(most < 1e-5);
  assert_true(covered(want) > 100);
  satf_image_destroy(want);
  satf_renderer_destroy(fresh);
}

/* The strand path keeps its deep opacity map while the light, the strands
 * and the scene stand (draw_dom_lights): the camera orbits for free, a
 * light that turns, a new scene state or new strands draw it again. */
static void test_strand_dom_reuse(void **state) {
  fixture_gl *f = *state;
  satf_scene *scene = fixture_scene(SCENE);
  assert_non_null(scene);
  satf_renderer *r = make(f, scene);
  assert_non_null(r);
  set_row_of_strands(r);
  satf_image *a = image(r), *b = image(r);
  assert_int_equal(r->dom.reuses, 1);
  assert_true(fixture_same_bits(a, b, "R"));
  assert_true(fixture_same_bits(a, b, "A"));
  /* the shadows are in the frame: without them it is brighter */
  r->effects.cluster_shadows = 0;
  satf_image *open = image(r);
  r->effects.cluster_shadows = 1;
  printf("the shadows' mean |dR| %.2g\n", mean_diff(a, open));
  assert_true(mean_diff(a, open) > 1e-3);
  /* the camera moves: kept */
  satf_renderer_camera(r)->position[0] += 3.0f;
  satf_image *c = image(r);
  assert_int_equal(r->dom.reuses, 2);
  assert_like_fresh(f, scene, r, c);
  /* the light turns: drawn again, then kept */
  satf_renderer_light(r, 0)->direction[0] += 0.3f;
  satf_image *d = image(r);
  assert_int_equal(r->dom.reuses, 2);
  assert_like_fresh(f, scene, r, d);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  /* a scene state (animation: the scene's camera and light again) and
   * new strands: drawn again */
  satf_error err;
  assert_int_equal(satf_renderer_set_scene(r, scene, NULL, &err), SATF_OK);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  set_row_of_strands(r);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  /* back to the clusters: their own map, not the strands' */
  assert_int_equal(
      satf_renderer_set_strands(r, 0, NULL, NULL, NULL, 0.0f, &err), SATF_OK);
  satf_image_destroy(image(r));
  assert_int_equal(r->dom.reuses, 3);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(open);
  satf_image_destroy(c);
  satf_image_destroy(d);
  satf_renderer_destroy(r);
  satf_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_instanced_same_image),
      cmocka_unit_test(test_shared_map_arrays),
      cmocka_unit_test(test_strand_dom_reuse),
      cmocka_unit_test(test_incremental_lookups),
      cmocka_unit_test(test_layers_split),
      cmocka_unit_test(test_dom_reuse),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
