/* test_relevel.c - a fibre database at other absorption levels
 * (db/relevel.c): the log-linear interpolation the record contract asks
 * for, exact on one exponential, and satf_db_relevel on a whole database. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "satf/db.h"
#include "test_util.h"

/* A lobe that falls as exp(-c sigma) (one internal path length c) is
 * reproduced exactly between levels and past the last one. */
static void test_level_value_exponential(void **state) {
  (void)state;
  const float levels[4] = {0.0f, 0.5f, 2.0f, 8.0f};
  float values[4];
  for (int k = 0; k < 4; k++)
    values[k] = 0.4f * expf(-1.7f * levels[k]);
  for (float s = 0.0f; s <= 12.0f; s += 0.25f)
    assert_near(satf_db_level_value(levels, values, 4, s), 0.4 * exp(-1.7 * s),
                1e-6 + 1e-4 * 0.4 * exp(-1.7 * s));
  /* below the first level the first value holds */
  assert_near(satf_db_level_value(levels + 1, values + 1, 3, 0.1f), values[1],
              1e-7);
}

/* A zero on either side falls back to linear; values never go negative
 * and never rise past the last level. */
static void test_level_value_edges(void **state) {
  (void)state;
  const float levels[3] = {0.0f, 1.0f, 2.0f};
  const float zero_end[3] = {0.5f, 0.2f, 0.0f};
  assert_near(satf_db_level_value(levels, zero_end, 3, 1.5f), 0.1, 1e-6);
  assert_near(satf_db_level_value(levels, zero_end, 3, 5.0f), 0.0, 1e-7);
  const float rising[3] = {0.1f, 0.2f, 0.3f};
  assert_near(satf_db_level_value(levels, rising, 3, 4.0f), 0.3, 1e-7);
  const float one[1] = {0.25f};
  assert_near(satf_db_level_value(levels, one, 1, 3.0f), 0.25, 1e-7);
}

/* A small fibre database whose lobes fall as exp(-c sigma) with c per
 * sample: re-levelled at three new levels, every absorbing channel is the
 * exponential there and the others are copied. */
static void test_relevel_database(void **state) {
  (void)state;
  satf_build_params p = satf_build_params_default_fiber();
  p.samples = 3;
  p.n_view = p.n_light = 4;
  p.trace.width = 4;
  p.fiber.levels = 3;
  p.fiber.sigma_a[0] = 0.0f;
  p.fiber.sigma_a[1] = 1.0f;
  p.fiber.sigma_a[2] = 4.0f;
  satf_db *db, *re;
  satf_error err;
  assert_int_equal(satf_db_create(&p, &db, &err), SATF_OK);
  int K = 3, w = 4;
  for (int i = 0; i < p.samples; i++) {
    float *f = satf_db_sample_features(db, i);
    f[0] = 0.2f * (float)i;
    f[1] = f[2] = 0.5f;
    for (int iv = 0; iv < 4; iv++)
      for (int il = 0; il < 4; il++) {
        float *ch = satf_db_record_channels_mut(db, i, iv, il);
        for (int x = 0; x < w; x++) {
          ch[SATF_DB_CH_ALPHA * w + x] = 0.5f;
          ch[SATF_DB_CH_R * w + x] = 0.125f;
          for (int k = 0; k < K; k++) {
            float s = p.fiber.sigma_a[k], c = 0.5f + 0.25f * (float)i;
            ch[SATF_DB_CH_TT(k) * w + x] = 0.25f * expf(-c * s);
            ch[SATF_DB_CH_TRT(k, K) * w + x] = 0.0625f * expf(-2.0f * c * s);
            ch[SATF_DB_CH_MS(k, K) * w + x] = 0.125f * expf(-3.0f * c * s);
          }
        }
      }
  }
  assert_int_equal(satf_db_finalize(db, &err), SATF_OK);
  const float sigma[3] = {0.3f, 0.9f, 2.5f};
  assert_int_equal(satf_db_relevel(db, sigma, 3, 2, &re, &err), SATF_OK);
  assert_int_equal(satf_db_channels(re), SATF_DB_FIBER_CHANNELS(3));
  int n;
  const float *lv = satf_db_absorption_levels(re, &n);
  assert_int_equal(n, 3);
  assert_true(lv[1] == 0.9f);
  for (int i = 0; i < p.samples; i++) {
    assert_true(satf_db_features(re, i)[0] == satf_db_features(db, i)[0]);
    const float *a = satf_db_record_channels(db, i, 1, 2);
    const float *b = satf_db_record_channels(re, i, 1, 2);
    for (int x = 0; x < w; x++) {
      assert_true(b[SATF_DB_CH_ALPHA * w + x] == a[SATF_DB_CH_ALPHA * w + x]);
      assert_true(b[SATF_DB_CH_R * w + x] == a[SATF_DB_CH_R * w + x]);
      /* the source holds half floats: compare with a relative 2e-3 */
      double c = 0.5 + 0.25 * i;
      for (int k = 0; k < 3; k++) {
        double tt = 0.25 * exp(-c * sigma[k]);
        double ms = 0.125 * exp(-3.0 * c * sigma[k]);
        assert_near(b[SATF_DB_CH_TT(k) * w + x], tt, 2e-3 * tt + 1e-6);
        assert_near(b[SATF_DB_CH_MS(k, 3) * w + x], ms, 2e-3 * ms + 1e-6);
      }
    }
  }
  /* a Phong database has no levels */
  satf_db *phong;
  satf_build_params pp = satf_build_params_default();
  pp.samples = 2;
  pp.n_view = pp.n_light = 4;
  pp.trace.width = 4;
  assert_int_equal(satf_db_create(&pp, &phong, &err), SATF_OK);
  satf_db *none = (satf_db *)1;
  assert_int_equal(satf_db_relevel(phong, sigma, 3, 1, &none, &err),
                   SATF_ERR_INCOMPATIBLE);
  assert_null(none);
  satf_db_destroy(phong);
  satf_db_destroy(re);
  satf_db_destroy(db);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_level_value_exponential),
      cmocka_unit_test(test_level_value_edges),
      cmocka_unit_test(test_relevel_database),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
