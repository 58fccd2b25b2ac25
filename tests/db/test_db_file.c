/* test_db_file.c - the HRIR-DB file format: round trip, and every way a
 * file can be wrong (truncated, corrupted, foreign, incompatible). */
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
#include "satf/offline.h"
#include "test_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static satf_db *g_db;
static unsigned char *g_bytes;
static size_t g_size;
static char g_path[512];

static int setup(void **state) {
  (void)state;
  satf_build_params p = satf_build_params_default();
  p.samples = 12;
  p.n_view = 6;
  p.n_light = 5;
  p.grid = 12;
  p.trace.width = 12;
  satf_error err;
  if (satf_build(&p, 0, NULL, NULL, &g_db, &err) != SATF_OK)
    return -1;
  test_path(g_path, sizeof g_path, "test_db_file.exr");
  if (satf_db_write(g_db, g_path, &err) != SATF_OK)
    return -1;
  g_bytes = test_read_file(g_path, &g_size);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  satf_db_destroy(g_db);
  free(g_bytes);
  return 0;
}

static void round_trip_is_exact(void **state) {
  (void)state;
  satf_db *back = NULL;
  satf_error err;
  assert_int_equal(satf_db_read(g_path, &back, &err), SATF_OK);
  assert_same_db(g_db, back);
  assert_true(satf_db_payload_hash(g_db) == satf_db_payload_hash(back));
  /* and writing what was read gives the same bytes */
  char again[512];
  test_path(again, sizeof again, "test_db_file_again.exr");
  assert_int_equal(satf_db_write(back, again, &err), SATF_OK);
  size_t n;
  unsigned char *bytes = test_read_file(again, &n);
  assert_int_equal(n, g_size);
  assert_memory_equal(bytes, g_bytes, n);
  free(bytes);
  satf_db_destroy(back);
}

static void the_file_is_an_image(void **state) {
  (void)state;
  const char *names[2] = {"Y", "A"};
  float *planes[2];
  int w, h;
  satf_error err;
  assert_int_equal(satf_exr_read(g_path, names, 2, 1 << 20, NULL, NULL, &w, &h,
                                 planes, &err),
                   SATF_OK);
  const satf_build_params *p = satf_db_params(g_db);
  assert_int_equal(w, p->n_view * p->trace.width);
  assert_int_equal(h, p->samples * p->n_light);
  /* pixel (iv * width + j, sample * n_light + il) is record sample j */
  const float *r, *a;
  satf_db_record(g_db, 7, 4, 3, &r, &a);
  for (int j = 0; j < p->trace.width; j++) {
    size_t px =
        (size_t)(7 * p->n_light + 3) * (size_t)w + 4 * p->trace.width + j;
    assert_float_equal(planes[0][px], r[j], 0);
    assert_float_equal(planes[1][px], a[j], 0);
  }
  free(planes[0]);
  free(planes[1]);
}

static void truncation_is_detected(void **state) {
  (void)state;
  char cut[512];
  test_path(cut, sizeof cut, "test_db_file_cut.exr");
  for (size_t n = 0; n < g_size; n += n < 600 ? 7 : 97) {
    test_write_file(cut, g_bytes, n);
    satf_db *db = NULL;
    satf_error err;
    satf_error_clear(&err);
    satf_status st = satf_db_read(cut, &db, &err);
    assert_int_not_equal(st, SATF_OK);
    assert_null(db);
    assert_non_null(strstr(err.message, cut));
  }
}

static void byte_flips_are_detected_or_harmless(void **state) {
  (void)state;
  char bad[512];
  test_path(bad, sizeof bad, "test_db_file_flip.exr");
  unsigned char *copy = malloc(g_size);
  satf_rng rng;
  satf_rng_seed(&rng, 5, 5);
  int detected = 0, harmless = 0;
  for (int k = 0; k < 400; k++) {
    memcpy(copy, g_bytes, g_size);
    size_t at = satf_rng_below(&rng, (uint32_t)g_size);
    copy[at] ^= (unsigned char)(1u << satf_rng_below(&rng, 8));
    test_write_file(bad, copy, g_size);
    satf_db *db = NULL;
    satf_error err;
    satf_error_clear(&err);
    if (satf_db_read(bad, &db, &err) == SATF_OK) {
      /* a flip in a byte the reader ignores (e.g. a standard attribute it
       * does not use) must leave every record intact */
      assert_same_db(g_db, db);
      satf_db_destroy(db);
      harmless++;
    } else {
      assert_true(err.message[0] != '\0');
      detected++;
    }
  }
  printf("byte flips: %d detected, %d in ignored bytes\n", detected, harmless);
  assert_true(detected > 350);
  free(copy);
}

/* Patches a 4-byte int attribute value in the raw header. */
static int patch_int_attr(unsigned char *bytes, size_t size, const char *name,
                          int32_t value) {
  size_t len = strlen(name);
  for (size_t i = 0; i + len + 13 < size && i < 100000; i++)
    if (memcmp(bytes + i, name, len + 1) == 0 &&
        memcmp(bytes + i + len + 1, "int", 4) == 0) {
      memcpy(bytes + i + len + 1 + 4 + 4, &value, 4);
      return 0;
    }
  return -1;
}

static void version_and_parameter_mismatch(void **state) {
  (void)state;
  char bad[512];
  test_path(bad, sizeof bad, "test_db_file_version.exr");
  unsigned char *copy = malloc(g_size);
  memcpy(copy, g_bytes, g_size);
  assert_int_equal(patch_int_attr(copy, g_size, "satf:version", 99), 0);
  test_write_file(bad, copy, g_size);
  satf_db *db = NULL;
  satf_error err;
  assert_int_equal(satf_db_read(bad, &db, &err), SATF_ERR_VERSION);
  assert_non_null(strstr(err.message, "version 99"));
  memcpy(copy, g_bytes, g_size);
  assert_int_equal(patch_int_attr(copy, g_size, "satf:width", 13), 0);
  test_write_file(bad, copy, g_size);
  assert_int_equal(satf_db_read(bad, &db, &err), SATF_ERR_CORRUPT);
  assert_non_null(strstr(err.message, "parameters say"));
  memcpy(copy, g_bytes, g_size);
  assert_int_equal(patch_int_attr(copy, g_size, "satf:samples", -5), 0);
  test_write_file(bad, copy, g_size);
  assert_int_equal(satf_db_read(bad, &db, &err), SATF_ERR_CORRUPT);
  assert_non_null(strstr(err.message, "samples"));
  free(copy);
}

static void foreign_and_missing_files(void **state) {
  (void)state;
  satf_db *db = NULL;
  satf_error err;
  char path[512];
  test_path(path, sizeof path, "no-such-file.exr");
  assert_int_equal(satf_db_read(path, &db, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, "no-such-file.exr"));
  test_path(path, sizeof path, "test_db_file_text.exr");
  test_write_file(path, (const unsigned char *)"hello, not an image\n", 20);
  assert_int_equal(satf_db_read(path, &db, &err), SATF_ERR_FORMAT);
  /* a real EXR image that is not a database */
  float px[4] = {0.1f, 0.2f, 0.3f, 0.4f};
  satf_exr_channel ch[1] = {{"Y", px}};
  satf_exr_write_opts o = {EXR_PIXEL_HALF, EXR_COMPRESSION_NONE, NULL, NULL, 0};
  test_path(path, sizeof path, "test_db_file_plain.exr");
  assert_int_equal(satf_exr_write(path, 2, 2, ch, 1, &o, &err), SATF_OK);
  assert_int_equal(satf_db_read(path, &db, &err), SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message, "not an satf HRIR database"));
  assert_null(db);
}

static void failed_write_leaves_nothing(void **state) {
  (void)state;
  satf_error err;
  const char *path = "/nonexistent-dir/db.exr";
  assert_int_equal(satf_db_write(g_db, path, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, path));
  satf_build_params p = satf_build_params_default();
  p.samples = 2;
  satf_db *raw = NULL;
  assert_int_equal(satf_db_create(&p, &raw, &err), SATF_OK);
  char out[512];
  test_path(out, sizeof out, "never-written.exr");
  assert_int_equal(satf_db_write(raw, out, &err), SATF_ERR_ARGUMENT);
  FILE *f = fopen(out, "rb");
  assert_null(f);
  satf_db_destroy(raw);
}

static void fuzz_entry_replays(void **state) {
  (void)state;
  /* the libFuzzer entry point on the valid file, a prefix and noise */
  assert_int_equal(LLVMFuzzerTestOneInput(g_bytes, g_size), 0);
  assert_int_equal(LLVMFuzzerTestOneInput(g_bytes, g_size / 2), 0);
  unsigned char noise[512];
  satf_rng rng;
  satf_rng_seed(&rng, 8, 8);
  for (int k = 0; k < 50; k++) {
    memcpy(noise, g_bytes, sizeof noise);
    for (int f = 0; f < 8; f++)
      noise[satf_rng_below(&rng, sizeof noise)] =
          (unsigned char)satf_rng_u64(&rng);
    assert_int_equal(LLVMFuzzerTestOneInput(noise, sizeof noise), 0);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip_is_exact),
      cmocka_unit_test(the_file_is_an_image),
      cmocka_unit_test(truncation_is_detected),
      cmocka_unit_test(byte_flips_are_detected_or_harmless),
      cmocka_unit_test(version_and_parameter_mismatch),
      cmocka_unit_test(foreign_and_missing_files),
      cmocka_unit_test(failed_write_leaves_nothing),
      cmocka_unit_test(fuzz_entry_replays),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
