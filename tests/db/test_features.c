/* test_features.c - density features (SATF sec. 5.2) and the k-d tree. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "kdtree.h"
#include "satf/common.h"
#include "satf/db.h"

static void features_by_hand(void **state) {
  (void)state;
  /* 3 x 2 grid (ns = 3 along s, nt = 2 along t):
   *   t=0: 0 1 2
   *   t=1: 0 0 3
   * mean = 6/6 = 1; s positions 0, .5, 1: centroid_s = (0.5*1 + 1*5)/6;
   * t positions 0, 1: centroid_t = 3/6 */
  float d[6] = {0, 1, 2, 0, 0, 3}, f[3];
  satf_density_features(d, 3, 2, f);
  assert_float_equal(f[0], 1.0f, 1e-6);
  assert_float_equal(f[1], 5.5f / 6.0f, 1e-6);
  assert_float_equal(f[2], 0.5f, 1e-6);
  float zero[6] = {0}, g[3];
  satf_density_features(zero, 3, 2, g);
  assert_float_equal(g[0], 0.0f, 0);
  assert_float_equal(g[1], 0.5f, 0);
  assert_float_equal(g[2], 0.5f, 0);
}

static void kdtree_matches_brute_force(void **state) {
  (void)state;
  enum { N = 500, Q = 200 };
  static float pts[N * 3];
  satf_rng rng;
  satf_rng_seed(&rng, 42, 0);
  for (int i = 0; i < N * 3; i++)
    pts[i] = (float)satf_rng_uniform(&rng);
  /* duplicates exercise the tie-break */
  memcpy(pts + 3 * 10, pts + 3 * 20, 3 * sizeof(float));
  satf_kdtree *t = satf_kdtree_build(pts, N);
  assert_non_null(t);
  for (int q = 0; q < Q; q++) {
    float x[3] = {(float)satf_rng_uniform(&rng), (float)satf_rng_uniform(&rng),
                  (float)satf_rng_uniform(&rng)};
    if (q == 0)
      memcpy(x, pts + 3 * 20, sizeof x);
    for (int k = 1; k <= 8; k++) {
      int idx[8];
      float d2[8];
      assert_int_equal(satf_kdtree_nearest(t, x, k, idx, d2), k);
      /* brute force: count points strictly closer than the k-th */
      for (int r = 0; r < k; r++) {
        const float *p = pts + 3 * idx[r];
        float e = (p[0] - x[0]) * (p[0] - x[0]) +
                  (p[1] - x[1]) * (p[1] - x[1]) + (p[2] - x[2]) * (p[2] - x[2]);
        assert_float_equal(e, d2[r], 1e-7);
        if (r > 0)
          assert_true(d2[r] >= d2[r - 1]);
        int closer = 0;
        for (int i = 0; i < N; i++) {
          const float *o = pts + 3 * i;
          float f = (o[0] - x[0]) * (o[0] - x[0]) +
                    (o[1] - x[1]) * (o[1] - x[1]) +
                    (o[2] - x[2]) * (o[2] - x[2]);
          closer += f < d2[r];
        }
        assert_true(closer <= r);
      }
    }
  }
  int idx[2];
  float d2[2];
  assert_int_equal(satf_kdtree_nearest(t, pts + 3 * 20, 2, idx, d2), 2);
  assert_int_equal(idx[0], 10); /* equal distance: lower index first */
  assert_int_equal(idx[1], 20);
  satf_kdtree_destroy(t);
  satf_kdtree *empty = satf_kdtree_build(pts, 0);
  assert_int_equal(satf_kdtree_nearest(empty, pts, 3, idx, d2), 0);
  satf_kdtree_destroy(empty);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(features_by_hand),
      cmocka_unit_test(kdtree_matches_brute_force),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
