/* test_trace.c - planar ray tracing (SATF sec. 5.1, eq. 5). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/math.h"
#include "satf/offline.h"

#define W 32

static satf_sector *make(void) {
  satf_sector_shape sh = satf_sector_shape_default();
  satf_sector *s = NULL;
  assert_int_equal(satf_sector_create(&sh, 32, 32, 0.01f, &s, NULL), SATF_OK);
  return s;
}

static void fill(satf_sector *s, float value) {
  for (int k = 0; k < s->ns * s->nt; k++)
    s->density[k] = value;
}

static void eq5_three_steps_by_hand(void **state) {
  (void)state;
  /* alpha = (0.2, 0.5, 1.0), re = (1.0, 0.5, 0.25):
   * step 1: w = 0.2            -> re 0.2, alpha 0.2
   * step 2: w = 0.5 * 0.8 = .4 -> re 0.2 + 0.2 = 0.4, alpha 0.6
   * step 3: w = 1.0 * 0.4 = .4 -> re 0.4 + 0.1 = 0.5, alpha 1.0 */
  float re = 0.0f, a = 0.0f;
  satf_accumulate(&re, &a, 0.2f, 1.0f);
  assert_float_equal(re, 0.2f, 1e-7);
  assert_float_equal(a, 0.2f, 1e-7);
  satf_accumulate(&re, &a, 0.5f, 0.5f);
  assert_float_equal(re, 0.4f, 1e-7);
  assert_float_equal(a, 0.6f, 1e-7);
  satf_accumulate(&re, &a, 1.0f, 0.25f);
  assert_float_equal(re, 0.5f, 1e-7);
  assert_float_equal(a, 1.0f, 1e-7);
}

static void step_opacity_is_exponential(void **state) {
  (void)state;
  assert_float_equal(satf_step_opacity(40.0f, 0.5f, 0.01f), 1 - expf(-0.2f),
                     1e-7);
  assert_float_equal(satf_step_opacity(40.0f, 0.0f, 0.01f), 0.0f, 0);
  /* two half steps compose to one full step */
  float half = satf_step_opacity(10.0f, 1.0f, 0.05f);
  float full = satf_step_opacity(10.0f, 1.0f, 0.1f);
  assert_float_equal(1 - (1 - half) * (1 - half), full, 1e-6);
}

static void phong_by_hand(void **state) {
  (void)state;
  satf_trace_params p = satf_trace_params_default();
  p.ambient = 0.1f;
  p.diffuse = 0.6f;
  p.specular = 0.3f;
  p.shininess = 2.0f;
  float n[2] = {1, 0}, l[2] = {1, 0}, v[2] = {1, 0};
  /* head-on: 0.1 + T (0.6 + 0.3) */
  assert_float_equal(satf_phong(&p, n, l, v, 0.5f), 0.1f + 0.5f * 0.9f, 1e-6);
  /* light at 60 deg, viewer on the mirror side at -60 deg:
   * n.l = 0.5, r = (0.5, -0.866) = v, so r.v = 1 */
  float l60[2] = {0.5f, 0.8660254f}, vm60[2] = {0.5f, -0.8660254f};
  assert_float_equal(satf_phong(&p, n, l60, vm60, 1.0f), 0.1f + 0.3f + 0.3f,
                     1e-5);
  /* light behind the normal: ambient only */
  float lb[2] = {-1, 0};
  assert_float_equal(satf_phong(&p, n, lb, v, 1.0f), 0.1f, 1e-7);
}

static void extent_of_default_sector(void **state) {
  (void)state;
  satf_sector_shape sh = satf_sector_shape_default();
  float lo, hi;
  satf_trace_extent(&sh, 0.0f, &lo, &hi); /* screen axis e = +y */
  float y = sinf(sh.phase_span / 2);
  assert_float_equal(lo, -y, 1e-6);
  assert_float_equal(hi, y, 1e-6);
  satf_trace_extent(&sh, SATF_PI_F / 2, &lo, &hi); /* e = -x */
  assert_float_equal(lo, -1.0f, 1e-6);
  assert_float_equal(hi, -0.8f * cosf(sh.phase_span / 2), 1e-6);
}

static void empty_sector_is_black_and_clear(void **state) {
  (void)state;
  satf_sector *s = make();
  satf_trace_params p = satf_trace_params_default();
  float re[W], a[W];
  for (int k = 0; k < 8; k++) {
    assert_int_equal(satf_trace_hrir(s, &p, k * 0.8f, k * 1.3f, re, a, NULL),
                     SATF_OK);
    for (int j = 0; j < W; j++) {
      assert_float_equal(re[j], 0.0f, 0);
      assert_float_equal(a[j], 0.0f, 0);
    }
  }
  satf_sector_destroy(s);
}

static void dense_sector_is_opaque(void **state) {
  (void)state;
  satf_sector *s = make();
  fill(s, 3.0f);
  satf_trace_params p = satf_trace_params_default();
  float re[W], a[W];
  float views[4] = {0.0f, SATF_PI_F, 0.4f, SATF_PI_F - 0.4f};
  for (int k = 0; k < 4; k++) {
    assert_int_equal(satf_trace_hrir(s, &p, views[k], 0.3f, re, a, NULL),
                     SATF_OK);
    /* rays in the middle half cross the whole depth; the record's edges
     * are blurred by the smoothing */
    for (int j = W / 4; j < 3 * W / 4; j++)
      assert_true(a[j] > 0.99f);
    for (int j = 0; j < W; j++)
      assert_true(re[j] > 0.0f && re[j] < 2.0f);
  }
  satf_sector_destroy(s);
}

static void alpha_grows_with_density(void **state) {
  (void)state;
  satf_build_params bp = satf_build_params_default();
  satf_sector *s = NULL;
  assert_int_equal(satf_build_sector(&bp, 11, 5, &s, NULL), SATF_OK);
  satf_trace_params p = satf_trace_params_default();
  float prev[W] = {0}, re[W], a[W];
  float scales[5] = {0.25f, 2.0f, 2.0f, 2.0f, 2.0f}; /* x0.25 .. x4 */
  for (int k = 0; k < 5; k++) {
    satf_sector_scale(s, scales[k]);
    assert_int_equal(satf_trace_hrir(s, &p, 0.2f, 1.0f, re, a, NULL), SATF_OK);
    float sum = 0, psum = 0;
    for (int j = 0; j < W; j++) {
      assert_true(a[j] >= prev[j]);
      sum += a[j];
      psum += prev[j];
    }
    assert_true(sum > psum);
    memcpy(prev, a, sizeof a);
  }
  satf_sector_destroy(s);
}

static void shadowing_only_darkens(void **state) {
  (void)state;
  satf_build_params bp = satf_build_params_default();
  satf_sector *s = NULL;
  assert_int_equal(satf_build_sector(&bp, 2, 9, &s, NULL), SATF_OK);
  satf_sector_scale(s, 4.0f);
  satf_trace_params lit = satf_trace_params_default(), dark = lit;
  lit.self_shadow = 0;
  float r0[W], a0[W], r1[W], a1[W];
  float sum0 = 0, sum1 = 0;
  /* light from behind the sector (towards the core): strands in front
   * are shaded by those nearer the light */
  assert_int_equal(
      satf_trace_hrir(s, &lit, 0.0f, SATF_PI_F - 0.3f, r0, a0, NULL), SATF_OK);
  assert_int_equal(
      satf_trace_hrir(s, &dark, 0.0f, SATF_PI_F - 0.3f, r1, a1, NULL), SATF_OK);
  for (int j = 0; j < W; j++) {
    assert_true(r1[j] <= r0[j] + 1e-6f);
    assert_float_equal(a0[j], a1[j], 0); /* opacity does not depend on light */
    sum0 += r0[j];
    sum1 += r1[j];
  }
  assert_true(sum1 < 0.9f * sum0);
  satf_sector_destroy(s);
}

static void all_pairs_equal_single_traces(void **state) {
  (void)state;
  satf_build_params bp = satf_build_params_default();
  satf_sector *s = NULL;
  assert_int_equal(satf_build_sector(&bp, 5, 3, &s, NULL), SATF_OK);
  satf_trace_params p = satf_trace_params_default();
  enum { NV = 6, NL = 5 };
  static float re[NV * NL * W], a[NV * NL * W];
  assert_int_equal(satf_trace_all(s, &p, NV, NL, re, a, NULL), SATF_OK);
  for (int iv = 0; iv < NV; iv++)
    for (int il = 0; il < NL; il++) {
      float r1[W], a1[W];
      float tv = 6.28318530717959f * (float)iv / NV;
      float tl = 6.28318530717959f * (float)il / NL;
      assert_int_equal(satf_trace_hrir(s, &p, tv, tl, r1, a1, NULL), SATF_OK);
      assert_memory_equal(r1, re + (iv * NL + il) * W, sizeof r1);
      assert_memory_equal(a1, a + (iv * NL + il) * W, sizeof a1);
    }
  satf_sector_destroy(s);
}

static void a_strand_appears_where_it_is(void **state) {
  (void)state;
  /* one dense clump at t = 0.8 seen head-on lands in the upper part of the
   * record (screen axis e = +y = increasing t) */
  satf_sector *s = make();
  for (int k = 0; k < 30; k++)
    satf_sector_add_strand(s, 0.5f, 0.8f);
  satf_trace_params p = satf_trace_params_default();
  float re[W], a[W];
  assert_int_equal(satf_trace_hrir(s, &p, 0.0f, 0.0f, re, a, NULL), SATF_OK);
  int best = 0;
  for (int j = 1; j < W; j++)
    if (a[j] > a[best])
      best = j;
  /* t = 0.8 -> phi = 0.3 span -> y = 0.9 sin(0.3 span), extent +-sin(span/2) */
  float y = 0.9f * sinf(0.3f * 0.3927f), ext = sinf(0.5f * 0.3927f);
  int expect = (int)((y + ext) / (2 * ext) * W);
  assert_true(abs(best - expect) <= 1);
  assert_true(a[0] < 0.01f);
  satf_sector_destroy(s);
}

static void bad_params_rejected(void **state) {
  (void)state;
  satf_sector *s = make();
  satf_trace_params p = satf_trace_params_default();
  float re[W], a[W];
  satf_error err;
  p.width = 1;
  assert_int_equal(satf_trace_hrir(s, &p, 0, 0, re, a, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "width"));
  p = satf_trace_params_default();
  p.extinction = NAN;
  assert_int_equal(satf_trace_hrir(s, &p, 0, 0, re, a, &err),
                   SATF_ERR_ARGUMENT);
  assert_int_equal(satf_trace_all(s, &p, 0, 4, re, a, &err), SATF_ERR_ARGUMENT);
  satf_sector_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(eq5_three_steps_by_hand),
      cmocka_unit_test(step_opacity_is_exponential),
      cmocka_unit_test(phong_by_hand),
      cmocka_unit_test(extent_of_default_sector),
      cmocka_unit_test(empty_sector_is_black_and_clear),
      cmocka_unit_test(dense_sector_is_opaque),
      cmocka_unit_test(alpha_grows_with_density),
      cmocka_unit_test(shadowing_only_darkens),
      cmocka_unit_test(all_pairs_equal_single_traces),
      cmocka_unit_test(a_strand_appears_where_it_is),
      cmocka_unit_test(bad_params_rejected),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
