/* test_db.c - database builds and the SATF look-up (eq. 4). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "db_compare.h"
#include "hrir_db_internal.h"
#include "satf/math.h"
#include "satf/offline.h"

static satf_build_params small(int samples) {
  satf_build_params p = satf_build_params_default();
  p.samples = samples;
  p.n_view = 8;
  p.n_light = 6;
  p.grid = 16;
  p.trace.width = 16;
  p.seed = 99;
  return p;
}

static satf_db *build(const satf_build_params *p, int threads) {
  satf_db *db = NULL;
  satf_error err;
  assert_int_equal(satf_build(p, threads, NULL, NULL, &db, &err), SATF_OK);
  return db;
}

static void same_database_on_one_and_two_threads(void **state) {
  (void)state;
  satf_build_params p = small(24);
  satf_db *a = build(&p, 1), *b = build(&p, 2), *c = build(&p, 3);
  assert_same_db(a, b);
  assert_same_db(a, c);
  assert_true(satf_db_payload_hash(a) == satf_db_payload_hash(b));
  assert_true(satf_db_payload_hash(a) == satf_db_payload_hash(c));
  p.seed++;
  satf_db *d = build(&p, 2);
  assert_true(satf_db_payload_hash(a) != satf_db_payload_hash(d));
  satf_db_destroy(a);
  satf_db_destroy(b);
  satf_db_destroy(c);
  satf_db_destroy(d);
}

static void stored_key_returns_the_record(void **state) {
  (void)state;
  satf_build_params p = small(40);
  satf_db *db = build(&p, 0);
  int w = p.trace.width;
  float re[64], al[64];
  for (int i = 0; i < p.samples; i += 3)
    for (int iv = 0; iv < p.n_view; iv++)
      for (int il = 0; il < p.n_light; il++) {
        const float *r, *a;
        satf_db_record(db, i, iv, il, &r, &a);
        /* Samples can share features (empty sectors); then the lower index
         * wins, whose record is what the look-up must return. */
        int idx;
        float d2;
        satf_db_nearest(db, satf_db_features(db, i), 1, &idx, &d2);
        satf_db_record(db, idx, iv, il, &r, &a);
        for (int k = 1; k <= 4; k += 3) {
          satf_db_lookup(
              db, satf_db_features(db, i), SATF_TWO_PI_F * iv / p.n_view,
              SATF_TWO_PI_F * il / p.n_light + (float)(k - 1) * SATF_TWO_PI_F,
              k, re, al);
          assert_memory_equal(re, r, (size_t)w * sizeof(float));
          assert_memory_equal(al, a, (size_t)w * sizeof(float));
        }
      }
  satf_db_destroy(db);
}

static void angles_interpolate_bilinearly_and_periodically(void **state) {
  (void)state;
  satf_build_params p = small(10);
  satf_db *db = build(&p, 0);
  int w = p.trace.width;
  const float *f = satf_db_features(db, 4);
  int idx;
  float d2;
  satf_db_nearest(db, f, 1, &idx, &d2);
  float re[64], al[64];
  /* a quarter of the way from view 7 to view 0 (wrapping), light 2 */
  float tv = SATF_TWO_PI_F * (7.25f / 8.0f), tl = SATF_TWO_PI_F * 2.0f / 6.0f;
  satf_db_lookup(db, f, tv, tl, 1, re, al);
  const float *r7, *a7, *r0, *a0;
  satf_db_record(db, idx, 7, 2, &r7, &a7);
  satf_db_record(db, idx, 0, 2, &r0, &a0);
  for (int j = 0; j < w; j++) {
    assert_float_equal(re[j], 0.75f * r7[j] + 0.25f * r0[j], 1e-5);
    assert_float_equal(al[j], 0.75f * a7[j] + 0.25f * a0[j], 1e-5);
  }
  float re2[64], al2[64];
  satf_db_lookup(db, f, tv - 3 * SATF_TWO_PI_F, tl + SATF_TWO_PI_F, 1, re2,
                 al2);
  for (int j = 0; j < w; j++)
    assert_float_equal(re[j], re2[j], 1e-5);
  satf_db_destroy(db);
}

/* RMS difference between direct planar ray tracing of held-out sectors and
 * the database look-up at the same (features, angles). */
static double held_out_error(int samples, int k) {
  satf_build_params p = small(samples);
  p.n_view = 8;
  p.n_light = 4;
  satf_db *db = build(&p, 0);
  int w = p.trace.width;
  double sum = 0;
  int count = 0;
  for (int h = 0; h < 60; h++) {
    satf_sector *s = NULL;
    assert_int_equal(satf_build_sector(&p, 12345, (uint64_t)h, &s, NULL),
                     SATF_OK);
    float f[3];
    satf_density_features(s->density, s->ns, s->nt, f);
    for (int a = 0; a < 4; a++) {
      float tv = SATF_TWO_PI_F * (float)(a % p.n_view) / p.n_view;
      float tl = SATF_TWO_PI_F * (float)((a * 3) % p.n_light) / p.n_light;
      float r0[64], a0[64], r1[64], a1[64];
      assert_int_equal(satf_trace_hrir(s, &p.trace, tv, tl, r0, a0, NULL),
                       SATF_OK);
      satf_db_lookup(db, f, tv, tl, k, r1, a1);
      for (int j = 0; j < w; j++) {
        sum += (r0[j] - r1[j]) * (r0[j] - r1[j]) +
               (a0[j] - a1[j]) * (a0[j] - a1[j]);
        count += 2;
      }
    }
    satf_sector_destroy(s);
  }
  satf_db_destroy(db);
  return sqrt(sum / count);
}

static void held_out_error_shrinks_with_samples(void **state) {
  (void)state;
  double e64 = held_out_error(64, 4);
  double e256 = held_out_error(256, 4);
  double e1024 = held_out_error(1024, 4);
  printf("held-out RMS error (k=4): 64 samples %.4f, 256 %.4f, 1024 %.4f\n",
         e64, e256, e1024);
  assert_true(e256 < e64);
  assert_true(e1024 < e256);
  assert_true(e1024 < 0.2);
}

/* Look-ups read the records as halfs where the processor converts them
 * (satf_db.rec16): the same values, bit for bit, as from the floats
 * (which any writable access makes them read again). Width 13: runs of
 * 26 and 13 values, so the 8-wide loop and its tail both run. */
static void half_records_give_the_float_lookups(void **state) {
  (void)state;
  satf_build_params p = small(48);
  p.trace.width = 13;
  satf_db *db = build(&p, 0);
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
  if (satf_cpu_has_f16c(1))
    assert_non_null(db->rec16);
#endif
  enum { N = 40 };
  float halfs[N][2 * 13], floats[N][2 * 13];
  memset(halfs, 0, sizeof halfs);
  memset(floats, 0, sizeof floats);
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) { /* drops the halfs; the values stay */
      satf_db_record_channels_mut(db, 0, 0, 0);
      assert_null(db->rec16);
    }
    for (int q = 0; q < N; q++) {
      float f[3] = {0.05f * (float)q, 0.3f + 0.01f * (float)q,
                    0.7f - 0.01f * (float)q};
      satf_db_neighbors nb;
      satf_db_neighbors_find(db, f, 1 + q % 4, &nb);
      float tv = 0.37f * (float)q, tl = 1.0f + 0.23f * (float)q;
      float *out = pass ? floats[q] : halfs[q];
      if (q % 2)
        satf_db_lookup_neighbors_range(db, &nb, tv, tl, 0, 2, out);
      else
        satf_db_lookup_neighbors_range(db, &nb, tv, tl, 1, 1, out);
    }
  }
  assert_memory_equal(halfs, floats, sizeof halfs);
  satf_db_destroy(db);
}

static void bad_build_params_rejected(void **state) {
  (void)state;
  satf_build_params p = small(0);
  satf_db *db = NULL;
  satf_error err;
  assert_int_equal(satf_build(&p, 1, NULL, NULL, &db, &err), SATF_ERR_ARGUMENT);
  assert_null(db);
  assert_non_null(strstr(err.message, "samples"));
  p = small(1000000);
  p.n_view = p.n_light = 1024;
  assert_int_equal(satf_build_params_check(&p, &err), SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "GB"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(same_database_on_one_and_two_threads),
      cmocka_unit_test(stored_key_returns_the_record),
      cmocka_unit_test(angles_interpolate_bilinearly_and_periodically),
      cmocka_unit_test(held_out_error_shrinks_with_samples),
      cmocka_unit_test(half_records_give_the_float_lookups),
      cmocka_unit_test(bad_build_params_rejected),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
