/* test_db_part.c - parts of one build (satf/db.h "Parts"): the ranges cover
 * every sample once, shard files round-trip and refuse damage, and the
 * merge of a build's shards is the one-process database bit for bit, while
 * missing, duplicated, foreign and malformed shards are refused with the
 * file named. */
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

enum { PARTS = 3 };

static satf_build_params g_p;
static satf_db *g_whole;
static char g_shard[PARTS][512];

static satf_build_params small_params(uint64_t seed) {
  satf_build_params p = satf_build_params_default();
  p.seed = seed;
  p.samples = 10;
  p.n_view = 5;
  p.n_light = 4;
  p.grid = 8;
  p.trace.width = 8;
  return p;
}

static int setup(void **state) {
  (void)state;
  g_p = small_params(7);
  satf_error err;
  if (satf_build(&g_p, 2, NULL, NULL, &g_whole, &err) != SATF_OK)
    return -1;
  for (int i = 0; i < PARTS; i++) {
    char name[64];
    snprintf(name, sizeof name, "test_db_part_%d.exr", i);
    test_path(g_shard[i], sizeof g_shard[i], name);
    satf_db_part *part = NULL;
    /* other thread counts per part: the values must not care */
    if (satf_build_part(&g_p, i, PARTS, 1 + i, NULL, NULL, &part, &err) !=
        SATF_OK)
      return -1;
    satf_status st = satf_db_part_write(part, g_shard[i], &err);
    satf_db_part_destroy(part);
    if (st != SATF_OK)
      return -1;
  }
  return 0;
}

static int teardown(void **state) {
  (void)state;
  satf_db_destroy(g_whole);
  return 0;
}

static void ranges_cover_every_sample_once(void **state) {
  (void)state;
  int cases[][2] = {{1, 1}, {10, 3}, {10, 10}, {7, 2}, {1000000, 7}, {5, 9}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    int samples = cases[c][0], parts = cases[c][1], next = 0;
    for (int i = 0; i < parts; i++) {
      int first, count;
      satf_db_part_range(samples, i, parts, &first, &count);
      assert_int_equal(first, next);
      assert_true(count >= samples / parts && count <= samples / parts + 1);
      next = first + count;
    }
    assert_int_equal(next, samples);
  }
}

static void merge_is_the_whole_build(void **state) {
  (void)state;
  /* any order of the files */
  const char *paths[PARTS] = {g_shard[2], g_shard[0], g_shard[1]};
  satf_db *db = NULL;
  satf_error err;
  assert_int_equal(satf_db_merge(paths, PARTS, &db, &err), SATF_OK);
  assert_same_db(g_whole, db);
  assert_true(satf_db_payload_hash(db) == satf_db_payload_hash(g_whole));
  satf_db_destroy(db);
}

static void shard_round_trip_is_exact(void **state) {
  (void)state;
  satf_db_part *part = NULL, *back = NULL;
  satf_error err;
  assert_int_equal(satf_build_part(&g_p, 1, PARTS, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  assert_int_equal(part->first, 3);
  assert_int_equal(part->count, 3);
  /* a part's values are the whole build's samples, already rounded */
  size_t per = satf_db_sample_floats(&g_p);
  const float *re, *alpha;
  satf_db_record(g_whole, part->first, 0, 0, &re, &alpha);
  assert_memory_equal(part->rec, re, per * part->count * sizeof(float));
  assert_memory_equal(part->features, satf_db_features(g_whole, part->first),
                      (size_t)part->count * SATF_FEATURES * sizeof(float));
  assert_int_equal(satf_db_part_read(g_shard[1], &back, &err), SATF_OK);
  assert_int_equal(back->index, 1);
  assert_int_equal(back->parts, PARTS);
  assert_true(satf_db_part_hash(back) == satf_db_part_hash(part));
  assert_memory_equal(back->rec, part->rec, per * part->count * sizeof(float));
  satf_db_part_destroy(part);
  satf_db_part_destroy(back);
}

static void hash_sees_every_field(void **state) {
  (void)state;
  satf_db_part *part = NULL;
  satf_error err;
  assert_int_equal(satf_build_part(&g_p, 0, PARTS, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  uint64_t h = satf_db_part_hash(part);
  part->rec[5] += 1.0f;
  assert_true(satf_db_part_hash(part) != h);
  part->rec[5] -= 1.0f;
  assert_true(satf_db_part_hash(part) == h);
  part->index = 1;
  assert_true(satf_db_part_hash(part) != h);
  part->index = 0;
  part->p.seed++;
  assert_true(satf_db_part_hash(part) != h);
  satf_db_part_destroy(part);
}

/* Merges the paths and expects failure with a message holding `want`. */
static void expect_merge_fails(const char *const *paths, int n,
                               const char *want) {
  satf_db *db = NULL;
  satf_error err;
  satf_error_clear(&err);
  assert_int_not_equal(satf_db_merge(paths, n, &db, &err), SATF_OK);
  assert_null(db);
  if (!strstr(err.message, want))
    fail_msg("merge error \"%s\" does not say \"%s\"", err.message, want);
}

static void merge_refuses_missing_duplicated_foreign(void **state) {
  (void)state;
  const char *missing[2] = {g_shard[0], g_shard[2]};
  expect_merge_fails(missing, 2, "shard 1/3 is missing");
  const char *dup[4] = {g_shard[0], g_shard[1], g_shard[1], g_shard[2]};
  expect_merge_fails(dup, 4, "shard 1/3 again");

  /* another seed: a shard of another build, named */
  char foreign[512], other_n[512];
  test_path(foreign, sizeof foreign, "test_db_part_foreign.exr");
  test_path(other_n, sizeof other_n, "test_db_part_other_n.exr");
  satf_build_params q = small_params(8);
  satf_db_part *part = NULL;
  satf_error err;
  assert_int_equal(satf_build_part(&q, 1, PARTS, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  assert_int_equal(satf_db_part_write(part, foreign, &err), SATF_OK);
  satf_db_part_destroy(part);
  const char *with_foreign[3] = {g_shard[0], foreign, g_shard[2]};
  expect_merge_fails(with_foreign, 3, foreign);
  expect_merge_fails(with_foreign, 3, "another build");

  /* same seed, other parameters */
  q = small_params(7);
  q.trace.extinction *= 2.0f;
  assert_int_equal(satf_build_part(&q, 1, PARTS, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  assert_int_equal(satf_db_part_write(part, foreign, &err), SATF_OK);
  satf_db_part_destroy(part);
  expect_merge_fails(with_foreign, 3, "build parameters differ");

  /* the same build cut in 4 */
  assert_int_equal(satf_build_part(&g_p, 1, 4, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  assert_int_equal(satf_db_part_write(part, other_n, &err), SATF_OK);
  satf_db_part_destroy(part);
  const char *mixed[3] = {g_shard[0], other_n, g_shard[2]};
  expect_merge_fails(mixed, 3, "shard 1/4");
  expect_merge_fails(mixed, 0, "no shard files");
}

static void shard_refuses_a_wrong_place(void **state) {
  (void)state;
  satf_db_part *part = NULL;
  satf_error err;
  assert_int_equal(satf_build_part(&g_p, 1, PARTS, 0, NULL, NULL, &part, &err),
                   SATF_OK);
  part->first = 4; /* shard 1/3 of 10 samples starts at 3 */
  char path[512];
  test_path(path, sizeof path, "test_db_part_misplaced.exr");
  assert_int_equal(satf_db_part_write(part, path, &err), SATF_OK);
  satf_db_part_destroy(part);
  satf_db_part *back = NULL;
  assert_int_equal(satf_db_part_read(path, &back, &err), SATF_ERR_CORRUPT);
  assert_null(back);
  assert_non_null(strstr(err.message, path));
  assert_non_null(strstr(err.message, "holds samples 4..6"));
}

static void database_is_not_a_shard_and_back(void **state) {
  (void)state;
  char path[512];
  test_path(path, sizeof path, "test_db_part_whole.exr");
  satf_error err;
  assert_int_equal(satf_db_write(g_whole, path, &err), SATF_OK);
  satf_db_part *part = NULL;
  assert_int_equal(satf_db_part_read(path, &part, &err), SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message, "not an satf database shard"));
  satf_db *db = NULL;
  assert_int_equal(satf_db_read(g_shard[0], &db, &err), SATF_ERR_FORMAT);
  assert_null(db);
}

/* Every truncation and a flip of each of many bytes: an error, never a
 * crash, and never a part that differs from the file's. */
static void damaged_shards_are_refused(void **state) {
  (void)state;
  size_t size = 0;
  unsigned char *bytes = test_read_file(g_shard[1], &size);
  assert_non_null(bytes);
  char path[512];
  test_path(path, sizeof path, "test_db_part_damaged.exr");
  satf_error err;
  size_t step = size / 97 + 1;
  for (size_t cut = 0; cut < size; cut += step) {
    test_write_file(path, bytes, cut);
    satf_db_part *part = NULL;
    assert_int_not_equal(satf_db_part_read(path, &part, &err), SATF_OK);
    assert_null(part);
    assert_non_null(strstr(err.message, path));
  }
  satf_db_part *good = NULL;
  assert_int_equal(satf_db_part_read(g_shard[1], &good, &err), SATF_OK);
  int refused = 0, flips = 0;
  for (size_t at = 0; at < size; at += step) {
    bytes[at] ^= 0x5a;
    test_write_file(path, bytes, size);
    bytes[at] ^= 0x5a;
    satf_db_part *part = NULL;
    flips++;
    if (satf_db_part_read(path, &part, &err) != SATF_OK) {
      refused++;
      continue;
    }
    /* a flip the file does not see (padding) must change nothing */
    assert_true(satf_db_part_hash(part) == satf_db_part_hash(good));
    satf_db_part_destroy(part);
  }
  assert_true(refused > flips / 2);
  satf_db_part_destroy(good);
  free(bytes);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(ranges_cover_every_sample_once),
      cmocka_unit_test(merge_is_the_whole_build),
      cmocka_unit_test(shard_round_trip_is_exact),
      cmocka_unit_test(hash_sees_every_field),
      cmocka_unit_test(merge_refuses_missing_duplicated_foreign),
      cmocka_unit_test(shard_refuses_a_wrong_place),
      cmocka_unit_test(database_is_not_a_shard_and_back),
      cmocka_unit_test(damaged_shards_are_refused),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
