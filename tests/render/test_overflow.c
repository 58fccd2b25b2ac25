/* test_overflow.c - exact compositing beyond the per-pixel arrays (64
 * fragments, SATF_MAX_FRAGMENTS): a pixel behind more clusters than that
 * keeps its nearest fragments, whatever order they arrive in, and the
 * renderer counts such pixels (satf_render_stats.overflow_pixels); kept
 * from the pool past the arrays (glsl/list_write.glsl), and by the
 * nearest passes where the pool is full. */
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

#include "lists.h"
#include "render_fixture.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "shaders.h"
#include "test_util.h"

#define W 64
#define H 64
#define NEAR 64 /* vertical copies: exactly what a pixel's arrays hold */
#define FAR 16  /* horizontal copies behind them all */
/* so many that the fragments past the slots (80 pixels of NEAR + FAR_FULL)
 * do not fit the pool of one per pixel (W x H = 4,096) */
#define FAR_FULL 72

typedef fixture_gl fixture;

FIXTURE_GL_GROUP(W, H)

/* One straight cluster copied `near` times along the view axis (0.05
 * apart, vertical) and, with far > 0, `far` times further back turned
 * horizontal (hair across: another colour under the same light). With
 * far_first the far copies are listed (so drawn, so arrive) first, and
 * each group far to near. Cluster shadows are off: the deep opacity map's
 * slabs follow the scene bounds, which the reference scene changes. */
static satf_scene *stack_scene_of(int near, int far, int far_first,
                                  int sparse) {
  size_t cap = 64 * 1024, len = 0;
  char *inst = malloc(cap), *json = malloc(cap + 1024);
  if (!inst || !json)
    return NULL;
  inst[0] = '\0';
  for (int g = 0; g < 2; g++) {
    int horizontal = g == (far_first ? 0 : 1), n = horizontal ? far : near;
    for (int k = 0; k < n; k++) {
      double z = horizontal ? -(near * 0.05 + 2.0 + (far - 1 - k) * 0.05)
                            : -(near - 1 - k) * 0.05;
      len += (size_t)snprintf(
          inst + len, cap - len, "%s{\"translate\": [0, 0, %.3f]%s}",
          len ? ", " : "", z,
          horizontal ? ", \"rotate\": {\"axis\": [0, 0, 1], \"angle\": 90}"
                     : "");
    }
  }
  /* sparse: each copy one strand along its axis (drawn as a strand:
   * sparse.c), 0.004 units wide, about 3% of a pixel: 64 of them still let
   * a fifth of what lies behind through, so keeping the wrong 64 shows */
  const char *density =
      sparse ? "{\"type\": \"tracks\", \"slices\": 5, \"strand_width\": 0.005,"
               " \"tracks\": [[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]]}"
             : "{\"strands\": 150, \"seed\": 7}";
  snprintf(json, cap + 1024,
           "{\"macro_clusters\": [{\"prototype\": {"
           "  \"trajectory\": [[0, -3, 0], [0, 3, 0]], \"a\": 0.8,"
           "  \"shell\": {\"layers\": 2, \"st\": 8, \"su\": 8},"
           "  \"density\": %s},"
           " \"instances\": [%s]}%s],"
           " \"camera\": {\"position\": [0, 0, 60], \"target\": [0, 0, 0],"
           "              \"fov_y\": 10},"
           " \"lights\": [{\"direction\": [-0.7, -0.1, -0.7]}],"
           " \"effects\": {\"cluster_shadows\": false},"
           " \"background\": [0, 0, 0]%s}",
           density, inst,
           /* with the strands, a cluster of shells behind the camera: a
            * scene of strands alone composites them without the arrays
            * (sparse_composite) */
           sparse ? ", {\"prototype\": {\"trajectory\": [[0, -1, 200], "
                    "[0, 1, 200]], \"a\": 0.5, \"shell\": {\"layers\": "
                    "2, \"st\": 4, \"su\": 8}}}"
                  : "",
           /* a strand's highlight noise follows its index, which the
            * listing order changes */
           sparse ? ", \"material\": {\"noise\": 0}" : "");
  satf_scene *s = fixture_scene(json);
  free(inst);
  free(json);
  return s;
}

static satf_scene *stack_scene(int near, int far, int far_first) {
  return stack_scene_of(near, far, far_first, 0);
}

/* The beauty pass of `scene` (exact compositing); *overflow from the
 * renderer's stats. */
static satf_image *render_stack(const fixture *f, const satf_scene *scene,
                                long *overflow) {
  satf_renderer *r = NULL;
  satf_image *img = NULL;
  satf_error err;
  satf_render_stats stats;
  if (satf_renderer_create(scene, f->db, W, H, 0, &r, &err) != SATF_OK ||
      satf_renderer_render_image(r, 0, &img, NULL, &err) != SATF_OK) {
    fprintf(stderr, "%s\n", err.message);
    satf_renderer_destroy(r);
    return NULL;
  }
  satf_renderer_stats(r, &stats);
  *overflow = stats.overflow_pixels;
  satf_renderer_destroy(r);
  return img;
}

static const char *const rgba[4] = {"R", "G", "B", "A"};

/* More than 64 clusters over a pixel (`far` behind the 64 near ones): the
 * frame is the same bit for bit twice and with the clusters listed (so
 * arriving) in the other order, and where the near clusters cover a pixel
 * fully it is the frame of the 64 nearest alone: the far ones were the
 * ones left out. Before, the first 64 to arrive were kept (here the far
 * ones: listed first). */
static void nearest_kept(fixture *f, int far) {
  satf_scene *far_first = stack_scene(NEAR, far, 1);
  satf_scene *near_first = stack_scene(NEAR, far, 0);
  satf_scene *nearest = stack_scene(NEAR, 0, 0);
  assert_non_null(far_first);
  assert_non_null(near_first);
  assert_non_null(nearest);
  long over_a = 0, over_b = 0, over_c = 0, over_ref = -1;
  satf_image *a = render_stack(f, far_first, &over_a);
  satf_image *b = render_stack(f, far_first, &over_b);
  satf_image *c = render_stack(f, near_first, &over_c);
  satf_image *ref = render_stack(f, nearest, &over_ref);
  assert_non_null(a);
  assert_non_null(b);
  assert_non_null(c);
  assert_non_null(ref);
  printf("%d behind: pixels over 64 fragments: %ld (%ld, %ld); 64 nearest "
         "alone: %ld\n",
         far, over_a, over_b, over_c, over_ref);
  assert_true(over_a > 0);
  assert_int_equal(over_a, over_b);
  assert_int_equal(over_a, over_c);
  assert_int_equal(over_ref, 0);
  for (int k = 0; k < 4; k++) {
    if (!fixture_same_bits(a, b, rgba[k]) || !fixture_same_bits(a, c, rgba[k]))
      fail_msg("%s differs between renders or drawing orders", rgba[k]);
  }
  const float *ra = fixture_plane(ref, "A");
  size_t compared = 0;
  double worst = 0.0;
  for (size_t i = 0; i < (size_t)W * H; i++) {
    if (!(ra[i] > 0.999f))
      continue; /* elsewhere the far clusters show through, as they should */
    compared++;
    for (int k = 0; k < 4; k++) {
      double d =
          fabs(fixture_plane(a, rgba[k])[i] - fixture_plane(ref, rgba[k])[i]);
      worst = d > worst ? d : worst;
    }
  }
  printf("%zu fully covered pixels: largest difference from the 64 nearest "
         "alone %.2e\n",
         compared, worst);
  assert_true(compared > 50);
  assert_true(worst <= 1e-3);
  satf_image_destroy(a);
  satf_image_destroy(b);
  satf_image_destroy(c);
  satf_image_destroy(ref);
  satf_scene_destroy(far_first);
  satf_scene_destroy(near_first);
  satf_scene_destroy(nearest);
}

/* The fragments past the slots held by the pool, read by the resolve. */
static void test_nearest_fragments_kept(void **state) {
  nearest_kept(*state, FAR);
}

/* The pool full: the nearest passes keep them. */
static void test_nearest_kept_pool_full(void **state) {
  nearest_kept(*state, FAR_FULL);
}

/* The arrays' depth for the pool: the fewest slots past which the
 * fragments fit the room given, counted from the pixels' counts. */
static void test_pool_slots(void **state) {
  (void)state;
  enum { N = 10100 };
  GLuint *counts = malloc(N * sizeof *counts);
  assert_non_null(counts);
  for (int i = 0; i < N; i++) /* 10,000 pixels of 3, 100 of 100 */
    counts[i] = i < 10000 ? 3u : 100u;
  /* past s slots: 100 (100 - s) fragments */
  assert_int_equal(lists_slots_within(counts, N, 5000), 50);
  assert_int_equal(lists_slots_within(counts, N, 4999), 51);
  assert_int_equal(lists_slots_within(counts, N, 8400), START_SLOTS);
  assert_int_equal(lists_slots_within(counts, N, 3600), SATF_MAX_FRAGMENTS);
  assert_int_equal(lists_slots_within(counts, N, 3599), SATF_MAX_FRAGMENTS);
  for (int i = 0; i < N; i++) /* none deeper than the first slots */
    counts[i] = (GLuint)(i % (START_SLOTS + 1));
  assert_int_equal(lists_slots_within(counts, N, 0), START_SLOTS);
  free(counts);
}

/* The same for sparse clusters drawn as their strands (sparse.c), whose
 * first nearest pass writes only depth keys (glsl/strand_fs.glsl): the
 * frame does not depend on the order the strands arrive in. */
static void test_nearest_strands_kept(void **state) {
  fixture *f = *state;
  satf_scene *far_first = stack_scene_of(NEAR, FAR, 1, 1);
  satf_scene *near_first = stack_scene_of(NEAR, FAR, 0, 1);
  assert_non_null(far_first);
  assert_non_null(near_first);
  long over_a = 0, over_c = 0;
  satf_image *a = render_stack(f, far_first, &over_a);
  satf_image *c = render_stack(f, near_first, &over_c);
  assert_non_null(a);
  assert_non_null(c);
  printf("strands: pixels over 64 fragments: %ld (%ld)\n", over_a, over_c);
  assert_true(over_a > 0);
  assert_int_equal(over_a, over_c);
  for (int k = 0; k < 4; k++)
    if (!fixture_same_bits(a, c, rgba[k]))
      fail_msg("%s differs between the strands' drawing orders", rgba[k]);
  satf_image_destroy(a);
  satf_image_destroy(c);
  satf_scene_destroy(far_first);
  satf_scene_destroy(near_first);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pool_slots),
      cmocka_unit_test(test_nearest_fragments_kept),
      cmocka_unit_test(test_nearest_kept_pool_full),
      cmocka_unit_test(test_nearest_strands_kept),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
