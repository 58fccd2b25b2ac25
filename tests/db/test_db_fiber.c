/* test_db_fiber.c - databases of fibre records (format version 2): the
 * channel API, the look-up over every channel, the file round trip and its
 * errors, a version 1 file written by satf before version 2 existed,
 * thread-count determinism and golden values. */
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
#include "satf/common.h"
#include "satf/math.h"
#include "satf/offline.h"
#include "test_util.h"

static satf_build_params small_fiber(void) {
  satf_build_params p = satf_build_params_default_fiber();
  p.samples = 6;
  p.n_view = 4;
  p.n_light = 6;
  p.grid = 12;
  p.trace.width = 8;
  p.fiber.sub_rays = 4;
  p.fiber.levels = 3;
  p.fiber.sigma_a[0] = 0.0f;
  p.fiber.sigma_a[1] = 1.0f;
  p.fiber.sigma_a[2] = 5.0f;
  return p;
}

static satf_db *g_db;
static char g_path[512];

static int setup(void **state) {
  (void)state;
  satf_build_params p = small_fiber();
  satf_error err;
  if (satf_build(&p, 2, NULL, NULL, &g_db, &err) != SATF_OK)
    return -1;
  test_path(g_path, sizeof g_path, "test_db_fiber.exr");
  return satf_db_write(g_db, g_path, &err) == SATF_OK ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  satf_db_destroy(g_db);
  return 0;
}

static void assert_same_channels(const satf_db *a, const satf_db *b) {
  const satf_build_params *p = satf_db_params(a);
  assert_int_equal(satf_db_channels(a), satf_db_channels(b));
  size_t n = (size_t)satf_db_channels(a) * (size_t)p->trace.width;
  for (int i = 0; i < p->samples; i++)
    for (int iv = 0; iv < p->n_view; iv++)
      for (int il = 0; il < p->n_light; il++)
        assert_memory_equal(satf_db_record_channels(a, i, iv, il),
                            satf_db_record_channels(b, i, iv, il),
                            n * sizeof(float));
}

static void channel_api(void **state) {
  (void)state;
  const satf_build_params *p = satf_db_params(g_db);
  int K = 3, count = 0;
  assert_int_equal(satf_db_kind(g_db), SATF_RECORD_FIBER);
  assert_int_equal(satf_db_channels(g_db), 3 + 3 * K);
  assert_int_equal(SATF_DB_CH_MS(K - 1, K), satf_db_channels(g_db) - 1);
  const float *lv = satf_db_absorption_levels(g_db, &count);
  assert_int_equal(count, K);
  assert_float_equal(lv[1], 1.0f, 0);
  assert_float_equal(lv[2], 5.0f, 0);
  /* satf_db_record: reflectance = R + TT0 + TRT0 + MS0 (rounded to half
   * as stored), alpha = channel 1 */
  int w = p->trace.width;
  double lit = 0.0;
  for (int i = 0; i < p->samples; i++)
    for (int iv = 0; iv < p->n_view; iv++)
      for (int il = 0; il < p->n_light; il++) {
        const float *re, *alpha;
        satf_db_record(g_db, i, iv, il, &re, &alpha);
        const float *c = satf_db_record_channels(g_db, i, iv, il);
        assert_ptr_equal(re, c);
        assert_ptr_equal(alpha, c + SATF_DB_CH_ALPHA * w);
        for (int j = 0; j < w; j++) {
          float sum = c[SATF_DB_CH_R * w + j] + c[SATF_DB_CH_TT(0) * w + j] +
                      c[SATF_DB_CH_TRT(0, K) * w + j] +
                      c[SATF_DB_CH_MS(0, K) * w + j];
          assert_float_equal(re[j], sum, 1e-3f * (1.0f + sum));
          assert_true(alpha[j] >= 0.0f && alpha[j] <= 1.0f);
          lit += re[j];
        }
      }
  assert_true(lit > 0.0);
  /* a Phong database has two channels and no levels */
  satf_build_params q = satf_build_params_default();
  assert_int_equal(satf_build_params_channels(&q), 2);
  assert_int_equal(satf_build_params_version(&q), 1);
  assert_int_equal(satf_build_params_version(p), 2);
}

/* The channel look-up blends every channel as satf_db_lookup_neighbors
 * blends reflectance and alpha. */
static void lookup_over_every_channel(void **state) {
  (void)state;
  const satf_build_params *p = satf_db_params(g_db);
  int w = p->trace.width, nc = satf_db_channels(g_db);
  float *all = malloc((size_t)nc * (size_t)w * sizeof(float));
  float *re = malloc((size_t)w * sizeof(float));
  float *alpha = malloc((size_t)w * sizeof(float));
  float feature[SATF_FEATURES] = {0.3f, 0.5f, 0.5f};
  satf_db_neighbors nb;
  satf_db_neighbors_find(g_db, feature, 3, &nb);
  assert_true(nb.count == 3);
  float tv = 0.7f, tl = 2.9f; /* between stored azimuths */
  satf_db_lookup_neighbors_channels(g_db, &nb, tv, tl, all);
  satf_db_lookup_neighbors(g_db, &nb, tv, tl, re, alpha);
  assert_memory_equal(all, re, (size_t)w * sizeof(float));
  assert_memory_equal(all + w, alpha, (size_t)w * sizeof(float));
  /* at a stored pair with one neighbour: the record itself */
  satf_db_neighbors one = {1, {2}, {1.0f}};
  satf_db_lookup_neighbors_channels(g_db, &one, SATF_TWO_PI_F / 4.0f,
                                    SATF_TWO_PI_F * 2.0f / 6.0f, all);
  assert_memory_equal(all, satf_db_record_channels(g_db, 2, 1, 2),
                      (size_t)nc * (size_t)w * sizeof(float));
  free(all);
  free(re);
  free(alpha);
}

/* A channel range blends those channels bit for bit as the full look-up
 * does, and the full look-up is SATF eq. 4 (the neighbours' weights times
 * the periodic bilinear weights of the four stored azimuth pairs), summed
 * here in double straight from the records. */
static void lookup_range_is_a_slice_of_eq4(void **state) {
  (void)state;
  const satf_build_params *p = satf_db_params(g_db);
  int w = p->trace.width, nc = satf_db_channels(g_db);
  float *all = malloc((size_t)nc * (size_t)w * sizeof(float));
  float *part = malloc((size_t)nc * (size_t)w * sizeof(float));
  assert_non_null(all);
  assert_non_null(part);
  float feature[SATF_FEATURES] = {0.4f, 0.45f, 0.55f};
  satf_db_neighbors nb;
  satf_db_neighbors_find(g_db, feature, 4, &nb);
  assert_true(nb.count >= 2);
  /* between stored azimuths, and across the periodic seam */
  /* and the floats around 2 pi (below it, and above: 6.2831855f is 2 pi
   * rounded up), where the grid's periodic wrap and the snap meet */
  const float angles[5][2] = {{0.7f, 2.9f},
                              {6.2f, 0.05f},
                              {-0.3f, 7.5f},
                              {6.2831850f, 6.2831855f},
                              {6.2831855f, -1e-7f}};
  for (int a = 0; a < 5; a++) {
    float tv = angles[a][0], tl = angles[a][1];
    satf_db_lookup_neighbors_channels(g_db, &nb, tv, tl, all);
    double fv = fmod(fmod(tv / SATF_TWO_PI * p->n_view, p->n_view) + p->n_view,
                     p->n_view);
    double fl =
        fmod(fmod(tl / SATF_TWO_PI * p->n_light, p->n_light) + p->n_light,
             p->n_light);
    int v0 = (int)floor(fv), l0 = (int)floor(fl);
    fv -= v0;
    fl -= l0;
    for (int c = 0; c < nc; c++)
      for (int x = 0; x < w; x++) {
        double want = 0.0;
        for (int n = 0; n < nb.count; n++)
          for (int k = 0; k < 4; k++) {
            int iv = (v0 + (k & 1)) % p->n_view;
            int il = (l0 + (k >> 1)) % p->n_light;
            double bw = ((k & 1) ? fv : 1 - fv) * ((k >> 1) ? fl : 1 - fl);
            want +=
                nb.weight[n] * bw *
                satf_db_record_channels(g_db, nb.index[n], iv, il)[c * w + x];
          }
        if (fabs(all[c * w + x] - want) > 1e-6 * (1.0 + fabs(want)))
          fail_msg("azimuths %d channel %d sample %d: %.8f, eq. 4 %.8f", a, c,
                   x, (double)all[c * w + x], want);
      }
    const int ranges[4][2] = {{0, 2}, {1, 3}, {2, 1}, {1, 0}};
    for (int r = 0; r < 4; r++) {
      int ch0 = ranges[r][0], count = r == 3 ? nc - 1 : ranges[r][1];
      satf_db_lookup_neighbors_range(g_db, &nb, tv, tl, ch0, count, part);
      assert_memory_equal(part, all + (size_t)ch0 * w,
                          (size_t)count * (size_t)w * sizeof(float));
    }
    /* fetching ahead changes nothing */
    satf_db_prefetch(g_db, &nb, tv, tl, 1, nc - 1);
    satf_db_lookup_neighbors_range(g_db, &nb, tv, tl, 0, nc, part);
    assert_memory_equal(part, all, (size_t)nc * (size_t)w * sizeof(float));
    /* nor does the look-up in its two steps (satf_db_cell), for a range */
    satf_db_cell cell;
    satf_db_cell_find(g_db, tv, tl, &cell);
    satf_db_prefetch_cell(g_db, &nb, &cell, 1, nc - 1);
    memset(part, 0, (size_t)nc * (size_t)w * sizeof(float));
    satf_db_lookup_cell_range(g_db, &nb, &cell, 1, nc - 1, part);
    assert_memory_equal(part, all + w,
                        (size_t)(nc - 1) * (size_t)w * sizeof(float));
  }
  free(all);
  free(part);
}

static void v2_round_trip(void **state) {
  (void)state;
  satf_db *back = NULL;
  satf_error err;
  assert_int_equal(satf_db_read(g_path, &back, &err), SATF_OK);
  assert_same_db(g_db, back);
  assert_same_channels(g_db, back);
  assert_true(satf_db_payload_hash(g_db) == satf_db_payload_hash(back));
  satf_db_destroy(back);
}

/* The hash covers every channel and the fibre parameters. */
static void hash_covers_channels_and_parameters(void **state) {
  (void)state;
  satf_db *copy = NULL;
  satf_error err;
  assert_int_equal(satf_db_read(g_path, &copy, &err), SATF_OK);
  uint64_t h = satf_db_payload_hash(copy);
  const satf_build_params *p = satf_db_params(copy);
  /* the last channel (MS at the last level) of the last record */
  float *c = satf_db_record_channels_mut(copy, p->samples - 1, p->n_view - 1,
                                         p->n_light - 1);
  int last = satf_db_channels(copy) - 1, w = p->trace.width;
  c[last * w + w - 1] += 0.5f;
  assert_true(satf_db_payload_hash(copy) != h);
  c[last * w + w - 1] -= 0.5f;
  assert_true(satf_db_payload_hash(copy) == h);
  satf_build_params q = *p;
  q.fiber.sigma_a[2] = 6.0f;
  satf_db *other = NULL;
  assert_int_equal(satf_db_create(&q, &other, &err), SATF_OK);
  satf_build_params r = *p;
  satf_db *same = NULL;
  assert_int_equal(satf_db_create(&r, &same, &err), SATF_OK);
  assert_true(satf_db_payload_hash(other) != satf_db_payload_hash(same));
  satf_db_destroy(other);
  satf_db_destroy(same);
  satf_db_destroy(copy);
}

static void truncated_and_corrupt_v2_files_fail(void **state) {
  (void)state;
  size_t size = 0;
  unsigned char *bytes = test_read_file(g_path, &size);
  char bad[512];
  test_path(bad, sizeof bad, "test_db_fiber_bad.exr");
  satf_db *db = NULL;
  satf_error err;
  /* truncated: half the file, and all but the last byte */
  size_t cuts[2] = {size / 2, size - 1};
  for (int i = 0; i < 2; i++) {
    test_write_file(bad, bytes, cuts[i]);
    assert_int_not_equal(satf_db_read(bad, &db, &err), SATF_OK);
    assert_null(db);
    assert_non_null(strstr(err.message, bad));
  }
  /* one flipped byte in the pixel data (the end of the file) */
  unsigned char *flip = malloc(size);
  memcpy(flip, bytes, size);
  flip[size - 40] ^= 0x5A;
  test_write_file(bad, flip, size);
  assert_int_not_equal(satf_db_read(bad, &db, &err), SATF_OK);
  assert_null(db);
  /* a tampered level in the header: the parameters no longer hash */
  memcpy(flip, bytes, size);
  const char key[] = "satf:absorption";
  unsigned char *at = NULL;
  for (size_t i = 0; i + sizeof key < size && !at; i++)
    if (memcmp(bytes + i, key, sizeof key - 1) == 0)
      at = flip + i;
  assert_non_null(at);
  /* name, NUL, "vfloat", NUL, size (4 bytes), then the levels: bump the
   * last level's exponent */
  unsigned char *value = at + sizeof key + strlen("vfloat") + 1 + 4;
  value[2 * 4 + 3] ^= 0x01;
  test_write_file(bad, flip, size);
  assert_int_equal(satf_db_read(bad, &db, &err), SATF_ERR_CORRUPT);
  assert_non_null(strstr(err.message, "integrity"));
  free(flip);
  free(bytes);
}

/* A version 1 file written by satf before format version 2 existed
 * (tests/db/data/db_v1.exr: satf-build --samples 6 --angles 4x3 --width 8
 * --grid 8 --seed 11 at commit eb1b3e2) still reads, and holds what
 * today's Phong build makes from the same parameters. */
static void version_1_file_still_reads(void **state) {
  (void)state;
  satf_db *old = NULL;
  satf_error err;
  assert_int_equal(satf_db_read(SATF_TEST_DATA_DIR "/db_v1.exr", &old, &err),
                   SATF_OK);
  assert_int_equal(satf_db_kind(old), SATF_RECORD_PHONG);
  assert_int_equal(satf_db_channels(old), 2);
  int count = -1;
  assert_null(satf_db_absorption_levels(old, &count));
  assert_int_equal(count, 0);
  satf_build_params p = *satf_db_params(old);
  assert_int_equal(p.samples, 6);
  assert_int_equal(p.trace.width, 8);
  satf_db *now = NULL;
  assert_int_equal(satf_build(&p, 2, NULL, NULL, &now, &err), SATF_OK);
  assert_same_db(old, now);
  assert_true(satf_db_payload_hash(old) == satf_db_payload_hash(now));
  /* and today's Phong writer still writes version 1 */
  char again[512];
  test_path(again, sizeof again, "test_db_fiber_v1.exr");
  assert_int_equal(satf_db_write(now, again, &err), SATF_OK);
  size_t b = 0;
  unsigned char *y = test_read_file(again, &b);
  const char key[] = "satf:version";
  int found = 0;
  for (size_t i = 0; i + sizeof key + 8 < b; i++)
    if (memcmp(y + i, key, sizeof key) == 0) {
      /* name, NUL, "int", NUL, size 4, value */
      const unsigned char *v = y + i + sizeof key + 4 + 4;
      assert_int_equal(v[0] | v[1] << 8 | v[2] << 16 | v[3] << 24, 1);
      found = 1;
    }
  assert_true(found);
  free(y);
  satf_db_destroy(now);
  satf_db_destroy(old);
}

/* Fibre builds are bit-identical for any thread count. */
static void fiber_build_independent_of_threads(void **state) {
  (void)state;
  satf_build_params p = small_fiber();
  satf_db *one = NULL;
  satf_error err;
  assert_int_equal(satf_build(&p, 1, NULL, NULL, &one, &err), SATF_OK);
  assert_same_db(one, g_db);
  assert_same_channels(one, g_db);
  satf_db_destroy(one);
}

/* Golden values: a few stored values of the small build (half floats).
 * They change when the tracer, the fibre model or the sector generator
 * does; then check the furnace and single-fibre tests and update them. */
static void golden_values(void **state) {
  (void)state;
  const satf_build_params *p = satf_db_params(g_db);
  int w = p->trace.width;
  struct {
    int sample, iv, il, ch, j;
    float value;
  } gold[] = {
      {1, 0, 0, SATF_DB_CH_ALPHA, 1, 0.5f},
      {1, 0, 0, SATF_DB_CH_R, 5, 0.00161170959f},
      {1, 0, 0, SATF_DB_CH_TRT(0, 3), 1, 0.0346374512f},
      {2, 1, 3, SATF_DB_CH_ALPHA, 2, 1.0f},
      {2, 1, 3, SATF_DB_CH_R, 6, 0.0284118652f},
      {2, 1, 3, SATF_DB_CH_TT(1), 6, 2.98023224e-07f},
      {2, 1, 3, SATF_DB_CH_TRT(0, 3), 6, 0.000281095505f},
      {2, 1, 3, SATF_DB_CH_MS(0, 3), 4, 0.0604553223f},
      {4, 3, 5, SATF_DB_CH_R, 6, 0.000590801239f},
      {4, 3, 5, SATF_DB_CH_TRT(0, 3), 2, 0.0113449097f},
  };
  for (size_t g = 0; g < sizeof gold / sizeof gold[0]; g++) {
    const float *c =
        satf_db_record_channels(g_db, gold[g].sample, gold[g].iv, gold[g].il);
    float v = c[gold[g].ch * w + gold[g].j];
    if (v != gold[g].value)
      print_error("golden %zu: got %.9g want %.9g\n", g, (double)v,
                  (double)gold[g].value);
    assert_true(v == gold[g].value);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(channel_api),
      cmocka_unit_test(lookup_over_every_channel),
      cmocka_unit_test(lookup_range_is_a_slice_of_eq4),
      cmocka_unit_test(v2_round_trip),
      cmocka_unit_test(hash_covers_channels_and_parameters),
      cmocka_unit_test(truncated_and_corrupt_v2_files_fail),
      cmocka_unit_test(version_1_file_still_reads),
      cmocka_unit_test(fiber_build_independent_of_threads),
      cmocka_unit_test(golden_values),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
