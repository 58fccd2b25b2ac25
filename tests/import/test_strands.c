/* test_strands.c - the strand readers and writers (satf/strands.h): round
 * trips of files the test writes, every malformed case rejected with its own
 * message, follow strands, fuzz replays, and the real data when present. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/import.h"
#include "test_util.h"

int fuzz_hair_one(const uint8_t *data, size_t size);
int fuzz_tfx_one(const uint8_t *data, size_t size);

static void put32(unsigned char *p, uint32_t v) { memcpy(p, &v, 4); }
static void putf(unsigned char *p, float v) { memcpy(p, &v, 4); }

/* Three strands of 2, 5 and 3 points with thickness. */
static satf_strand_set *small_set(void) {
  int counts[3] = {2, 5, 3};
  float pts[30], th[10];
  for (int k = 0; k < 10; k++) {
    pts[3 * k] = 0.5f * (float)k;
    pts[3 * k + 1] = -1.25f + (float)(k * k) * 0.125f;
    pts[3 * k + 2] = 3.0f - (float)k;
    th[k] = 0.01f * (float)(k + 1);
  }
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(3, counts, pts, th, &s, &err),
                   SATF_OK);
  return s;
}

static void assert_same_set(const satf_strand_set *a, const satf_strand_set *b,
                            int thickness) {
  assert_int_equal(satf_strand_set_count(a), satf_strand_set_count(b));
  assert_int_equal(satf_strand_set_point_count(a),
                   satf_strand_set_point_count(b));
  for (int i = 0; i < satf_strand_set_count(a); i++) {
    int na, nb;
    const float *pa = satf_strand_set_strand(a, i, &na);
    const float *pb = satf_strand_set_strand(b, i, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(pa, pb, 3 * (size_t)na * sizeof(float));
    if (thickness)
      assert_memory_equal(satf_strand_set_thickness(a, i),
                          satf_strand_set_thickness(b, i),
                          (size_t)na * sizeof(float));
  }
}

static void hair_round_trip(void **state) {
  (void)state;
  satf_strand_set *s = small_set(), *back;
  char path[512];
  satf_error err;
  test_path(path, sizeof path, "rt.hair");
  assert_int_equal(satf_hair_write(path, s, &err), SATF_OK);
  /* 128 header + 3 x u16 + 10 x 12 + 10 x 4 */
  size_t size;
  unsigned char *bytes = test_read_file(path, &size);
  assert_int_equal(size, 128 + 6 + 120 + 40);
  free(bytes);
  assert_int_equal(satf_hair_read(path, &back, &err), SATF_OK);
  assert_same_set(s, back, 1);
  assert_float_equal(satf_strand_set_length(back, 0),
                     sqrtf(0.25f + 0.015625f + 1.0f), 1e-6);
  satf_strand_set_destroy(back);
  satf_strand_set_destroy(s);
}

/* A file without a thickness array gives its header's default thickness,
 * unless the defaults are cyHair's initial ones (thickness 1, transparency
 * 0, white), which a writer that never set them leaves: then none. */
static void hair_default_thickness(void **state) {
  (void)state;
  int counts[1] = {3};
  float pts[9] = {0, 0, 0, 0, 1, 0, 0, 2, 0};
  satf_strand_set *s, *back;
  satf_error err;
  assert_int_equal(satf_strand_set_create(1, counts, pts, NULL, &s, &err),
                   SATF_OK);
  char path[512];
  test_path(path, sizeof path, "nothick.hair");
  assert_int_equal(satf_hair_write(path, s, &err), SATF_OK);
  assert_int_equal(satf_hair_read(path, &back, &err), SATF_OK);
  assert_null(satf_strand_set_thickness(back, 0));
  satf_strand_set_destroy(back);
  size_t size;
  unsigned char *bytes = test_read_file(path, &size);
  /* a set default thickness is kept; so is 1 with another default beside */
  const float sets[][3] = {
      {0.25f, 0.0f, 1.0f}, {1.0f, 0.5f, 1.0f}, {1.0f, 0.0f, 0.2f}};
  for (int k = 0; k < 3; k++) {
    putf(bytes + 20, sets[k][0]);
    putf(bytes + 24, sets[k][1]);
    putf(bytes + 28, sets[k][2]);
    test_write_file(path, bytes, size);
    assert_int_equal(satf_hair_read(path, &back, &err), SATF_OK);
    const float *th = satf_strand_set_thickness(back, 0);
    assert_non_null(th);
    assert_float_equal(th[2], sets[k][0], 0.0f);
    satf_strand_set_destroy(back);
  }
  free(bytes);
  satf_strand_set_destroy(s);
}

static void tfx_round_trips(void **state) {
  (void)state;
  enum { N = 40, V = 12 };
  int counts[N];
  float *pts = malloc(3 * N * V * sizeof(float));
  for (int i = 0; i < N; i++) {
    counts[i] = V;
    for (int k = 0; k < V; k++) {
      float *p = pts + 3 * (i * V + k);
      p[0] = (float)(i % 8) * 0.7f + 0.05f * (float)k;
      p[1] = 10.0f - (float)k;
      p[2] = (float)(i / 8) * 0.7f + 0.1f * sinf((float)k);
    }
  }
  satf_strand_set *s, *back;
  satf_error err;
  assert_int_equal(satf_strand_set_create(N, counts, pts, NULL, &s, &err),
                   SATF_OK);
  free(pts);
  for (int version = 3; version <= 4; version++) {
    char path[512];
    test_path(path, sizeof path, version == 3 ? "rt3.tfx" : "rt4.tfx");
    assert_int_equal(
        satf_tfx_write(path, s, version, version == 3 ? 5 : 0, &err), SATF_OK);
    size_t size;
    unsigned char *bytes = test_read_file(path, &size);
    assert_int_equal(size, version == 3 ? 296 + 12 * N * V : 160 + 16 * N * V);
    free(bytes);
    satf_tfx_info info;
    assert_int_equal(satf_tfx_read(path, &info, &back, &err), SATF_OK);
    assert_float_equal(info.version, (float)version, 0);
    assert_int_equal(info.guides, N);
    assert_int_equal(info.vertices, V);
    assert_int_equal(info.follow_per_guide, version == 3 ? 5 : 0);
    assert_same_set(s, back, 0);
    satf_strand_set_destroy(back);
  }
  /* unequal strands cannot be a .tfx */
  satf_strand_set *odd = small_set();
  char path[512];
  test_path(path, sizeof path, "odd.tfx");
  assert_int_equal(satf_tfx_write(path, odd, 3, 0, &err), SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "share one vertex count"));
  satf_strand_set_destroy(odd);
  satf_strand_set_destroy(s);
}

/* A valid in-memory .hair: 2 strands of 2 and 3 points, segments array. */
static unsigned char *valid_hair(size_t *size) {
  *size = 128 + 4 + 5 * 12;
  unsigned char *b = calloc(1, *size);
  memcpy(b, "HAIR", 4);
  put32(b + 4, 2);
  put32(b + 8, 5);
  put32(b + 12, 3);
  b[128] = 1;
  b[130] = 2;
  for (int k = 0; k < 15; k++)
    putf(b + 132 + 4 * k, (float)k);
  return b;
}

static void expect_hair_error(const unsigned char *b, size_t size,
                              satf_status status, const char *message) {
  satf_strand_set *s = (satf_strand_set *)1;
  satf_error err;
  assert_int_equal(satf_hair_parse(b, size, "bad.hair", &s, &err), status);
  assert_null(s);
  if (!strstr(err.message, message))
    fail_msg("expected \"%s\" in \"%s\"", message, err.message);
  assert_non_null(strstr(err.message, "bad.hair"));
}

static void hair_malformed(void **state) {
  (void)state;
  size_t size;
  unsigned char *b = valid_hair(&size);
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_hair_parse(b, size, "ok.hair", &s, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(s), 2);
  assert_int_equal(satf_strand_set_points(s, 1), 3);
  assert_float_equal(satf_strand_set_strand(s, 1, NULL)[0], 6.0f, 0);
  satf_strand_set_destroy(s);

  expect_hair_error(b, 100, SATF_ERR_FORMAT, "truncated header");
  expect_hair_error(b, size - 1, SATF_ERR_CORRUPT, "truncated: 191 bytes");
  unsigned char *c = malloc(size);
#define MUTATE(stmt, status, msg)                                              \
  memcpy(c, b, size);                                                          \
  stmt;                                                                        \
  expect_hair_error(c, size, status, msg)
  MUTATE(c[0] = 'X', SATF_ERR_FORMAT, "not a cyHair file");
  MUTATE(put32(c + 4, 0), SATF_ERR_CORRUPT, "holds no strands");
  MUTATE(put32(c + 4, 3000000000u), SATF_ERR_CORRUPT, "absurd strand count");
  MUTATE(put32(c + 8, 4000000000u), SATF_ERR_CORRUPT, "absurd point count");
  MUTATE(put32(c + 12, 1), SATF_ERR_FORMAT, "no points array");
  MUTATE(put32(c + 12, 0x43), SATF_ERR_CORRUPT, "unknown bits");
  MUTATE(put32(c + 8, 6), SATF_ERR_CORRUPT, "truncated");
  MUTATE(put32(c + 8, 4), SATF_ERR_CORRUPT, "counts do not add up");
  MUTATE((put32(c + 12, 2), put32(c + 4, 100)), SATF_ERR_CORRUPT,
         "100 strands need at least 200 points");
  MUTATE(c[130] = 0, SATF_ERR_CORRUPT, "strand 1 has no segment");
  MUTATE(putf(c + 132 + 4 * 7, NAN), SATF_ERR_CORRUPT,
         "point value 7 is not finite");
  MUTATE(putf(c + 132, INFINITY), SATF_ERR_CORRUPT, "not finite");
  /* without a segments array every strand has the default count */
  memcpy(c, b, size);
  put32(c + 12, 2);
  put32(c + 16, 0);
  put32(c + 8, 4);
  expect_hair_error(c, size - 4, SATF_ERR_CORRUPT, "strand 0 has no segment");
  put32(c + 16, 1);
  assert_int_equal(satf_hair_parse(c, 128 + 48, "d.hair", &s, &err), SATF_OK);
  assert_int_equal(satf_strand_set_points(s, 1), 2);
  satf_strand_set_destroy(s);
#undef MUTATE
  free(c);
  free(b);
  /* a missing file names itself */
  assert_int_equal(satf_hair_read("/nonexistent/x.hair", &s, &err),
                   SATF_ERR_IO);
  assert_non_null(strstr(err.message, "/nonexistent/x.hair"));
}

/* A valid in-memory TressFX 3 file: 2 strands of 3 vertices. */
static unsigned char *valid_tfx3(size_t *size) {
  *size = 296 + 2 * 3 * 12;
  unsigned char *b = calloc(1, *size);
  putf(b, 3.0f);
  put32(b + 4, 2);
  put32(b + 8, 3);
  put32(b + 12, 4);
  put32(b + 144, 296);
  for (int k = 0; k < 18; k++)
    putf(b + 296 + 4 * k, 0.5f * (float)k);
  return b;
}

static void expect_tfx_error(const unsigned char *b, size_t size,
                             satf_status status, const char *message) {
  satf_strand_set *s = (satf_strand_set *)1;
  satf_error err;
  assert_int_equal(satf_tfx_parse(b, size, "bad.tfx", NULL, &s, &err), status);
  assert_null(s);
  if (!strstr(err.message, message))
    fail_msg("expected \"%s\" in \"%s\"", message, err.message);
  assert_non_null(strstr(err.message, "bad.tfx"));
}

static void tfx_malformed(void **state) {
  (void)state;
  size_t size;
  unsigned char *b = valid_tfx3(&size);
  satf_strand_set *s;
  satf_error err;
  satf_tfx_info info;
  assert_int_equal(satf_tfx_parse(b, size, "ok.tfx", &info, &s, &err), SATF_OK);
  assert_int_equal(info.follow_per_guide, 4);
  assert_float_equal(satf_strand_set_strand(s, 1, NULL)[0], 4.5f, 0);
  satf_strand_set_destroy(s);
  /* an offset of 0 means right after the header */
  unsigned char *c = malloc(size);
  memcpy(c, b, size);
  put32(c + 144, 0);
  assert_int_equal(satf_tfx_parse(c, size, "ok.tfx", NULL, &s, &err), SATF_OK);
  satf_strand_set_destroy(s);

  expect_tfx_error(b, 200, SATF_ERR_FORMAT, "truncated header");
  expect_tfx_error(b, 2, SATF_ERR_FORMAT, "truncated header");
  expect_tfx_error(b, size - 1, SATF_ERR_CORRUPT, "truncated: 2 strands x 3");
#define MUTATE(stmt, status, msg)                                              \
  memcpy(c, b, size);                                                          \
  stmt;                                                                        \
  expect_tfx_error(c, size, status, msg)
  /* a first float no TressFX file has: not TressFX, never "version 2e+09" */
  MUTATE(putf(c, 2.0e9f), SATF_ERR_FORMAT, "unrecognised format; satf reads");
  MUTATE(putf(c, NAN), SATF_ERR_FORMAT, "unrecognised format; satf reads");
  MUTATE(putf(c, 0.5f), SATF_ERR_FORMAT, "unrecognised format; satf reads");
  MUTATE(putf(c, 3.7f), SATF_ERR_VERSION, "not supported");
  MUTATE(put32(c + 4, 0), SATF_ERR_CORRUPT, "holds no strands");
  MUTATE(put32(c + 4, 2000000000u), SATF_ERR_CORRUPT, "absurd strand count");
  MUTATE(put32(c + 8, 1), SATF_ERR_CORRUPT, "strands with no segment");
  MUTATE(put32(c + 8, 100000), SATF_ERR_CORRUPT, "absurd 100000 vertices");
  MUTATE(put32(c + 12, 5000000), SATF_ERR_CORRUPT, "absurd 5000000 follow");
  MUTATE(put32(c + 4, 3), SATF_ERR_CORRUPT, "truncated: 3 strands x 3");
  MUTATE(put32(c + 144, 100), SATF_ERR_CORRUPT,
         "vertex position offset 100 lies outside");
  MUTATE(put32(c + 148, 99999), SATF_ERR_CORRUPT,
         "thickness offset 99999 lies outside");
  MUTATE(putf(c + 296 + 4 * 13, NAN), SATF_ERR_CORRUPT,
         "strand 1 vertex 1 is not finite");
  MUTATE(putf(c + 296, -INFINITY), SATF_ERR_CORRUPT,
         "strand 0 vertex 0 is not finite");
#undef MUTATE
  free(c);
  free(b);
  /* TressFX 4: float4 positions; offset 0 means absent */
  size = 160 + 2 * 2 * 16;
  b = calloc(1, size);
  putf(b, 4.0f);
  put32(b + 4, 2);
  put32(b + 8, 2);
  put32(b + 12, 160);
  for (int k = 0; k < 4; k++)
    for (int e = 0; e < 4; e++)
      putf(b + 160 + 16 * k + 4 * e, e == 3 ? 1.0f : (float)(10 * k + e));
  assert_int_equal(satf_tfx_parse(b, size, "ok4.tfx", &info, &s, &err),
                   SATF_OK);
  assert_float_equal(satf_strand_set_strand(s, 1, NULL)[3], 30.0f, 0);
  assert_int_equal(info.follow_per_guide, 0);
  satf_strand_set_destroy(s);
  expect_tfx_error(b, size - 4, SATF_ERR_CORRUPT, "truncated");
  expect_tfx_error(b, 150, SATF_ERR_FORMAT, "TressFX 4 header has 160");
  put32(b + 12, 0);
  expect_tfx_error(b, size, SATF_ERR_CORRUPT, "no vertex positions");
  free(b);
}

static void strand_set_rejects(void **state) {
  (void)state;
  int counts[2] = {2, 1};
  float pts[9] = {0};
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(2, counts, pts, NULL, &s, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "strand 1 has 1 points"));
  counts[0] = 3;
  counts[1] = 2;
  float more[15] = {0};
  more[4] = NAN;
  assert_int_equal(satf_strand_set_create(2, counts, more, NULL, &s, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "point 1 is not finite"));
}

/* Followers of a straight guide along +y: roots inside the disk of the
 * radius in the plane y = root, the offset constant in direction and grown
 * by exactly (1 + tip_separation) at the tip. */
static void follow_strands(void **state) {
  (void)state;
  enum { V = 9 };
  int counts[2] = {V, V};
  float pts[2 * V * 3];
  for (int i = 0; i < 2; i++)
    for (int k = 0; k < V; k++) {
      pts[3 * (i * V + k)] = 5.0f * (float)i;
      pts[3 * (i * V + k) + 1] = (float)k;
      pts[3 * (i * V + k) + 2] = 0.0f;
    }
  satf_strand_set *g, *f;
  satf_error err;
  assert_int_equal(satf_strand_set_create(2, counts, pts, NULL, &g, &err),
                   SATF_OK);
  assert_float_equal(satf_strand_set_root_spacing(g), 5.0f, 1e-6);
  satf_follow_params p = {6, 0.4f, 1.5f, 3};
  assert_int_equal(satf_strand_set_add_follow(g, &p, &f, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(f), 14);
  for (int i = 0; i < 14; i++) {
    int guide = i / 7;
    const float *q = satf_strand_set_strand(f, i, NULL);
    const float *r = satf_strand_set_strand(g, guide, NULL);
    float ox = q[0] - r[0], oz = q[2] - r[2];
    float root = sqrtf(ox * ox + oz * oz);
    if (i % 7 == 0) {
      assert_memory_equal(q, r, V * 3 * sizeof(float));
      continue;
    }
    assert_true(root <= 0.4f + 1e-6f);
    assert_float_equal(q[1], 0.0f, 1e-6);
    const float *tip = q + 3 * (V - 1);
    assert_float_equal(tip[1], (float)(V - 1), 1e-5);
    assert_float_equal(tip[0] - r[0], 2.5f * ox, 1e-5);
    assert_float_equal(tip[2] - r[2], 2.5f * oz, 1e-5);
  }
  /* deterministic for a seed */
  satf_strand_set *again;
  assert_int_equal(satf_strand_set_add_follow(g, &p, &again, &err), SATF_OK);
  assert_same_set(f, again, 0);
  satf_strand_set_destroy(again);
  p.count = SATF_STRANDS_MAX_FOLLOW + 1;
  assert_int_equal(satf_strand_set_add_follow(g, &p, &again, &err),
                   SATF_ERR_ARGUMENT);
  satf_strand_set_destroy(f);
  satf_strand_set_destroy(g);
}

static void concat_sets(void **state) {
  (void)state;
  satf_strand_set *a = small_set(), *b = small_set(), *c;
  satf_error err;
  assert_int_equal(satf_strand_set_concat(a, b, &c, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(c), 6);
  assert_int_equal(satf_strand_set_point_count(c), 20);
  assert_memory_equal(satf_strand_set_strand(c, 4, NULL),
                      satf_strand_set_strand(b, 1, NULL), 15 * sizeof(float));
  satf_strand_set_destroy(a);
  satf_strand_set_destroy(b);
  satf_strand_set_destroy(c);
}

static void fuzz_replays(void **state) {
  (void)state;
  size_t size;
  unsigned char *b = valid_hair(&size);
  test_replay_mutations(fuzz_hair_one, b, size);
  free(b);
  b = valid_tfx3(&size);
  test_replay_mutations(fuzz_tfx_one, b, size);
  free(b);
  char path[512];
  satf_strand_set *s = small_set();
  satf_error err;
  test_path(path, sizeof path, "replay.hair");
  assert_int_equal(satf_hair_write(path, s, &err), SATF_OK);
  satf_strand_set_destroy(s);
  b = test_read_file(path, &size);
  test_replay_mutations(fuzz_hair_one, b, size);
  free(b);
}

#ifndef SATF_SHARED_DATA_DIR
#define SATF_SHARED_DATA_DIR "../shared/data"
#endif

/* The real assets of ../shared/data, when this checkout has them. */
static void real_data(void **state) {
  (void)state;
  char path[1024];
  snprintf(path, sizeof path, "%s/hair/ponytail_side.tfx",
           SATF_SHARED_DATA_DIR);
  FILE *f = fopen(path, "rb");
  if (!f) {
    print_message("skipped: %s is absent (the shared data lives outside "
                  "the repository)\n",
                  path);
    skip();
  }
  fclose(f);
  satf_strand_set *s;
  satf_tfx_info info;
  satf_error err;
  assert_int_equal(satf_tfx_read(path, &info, &s, &err), SATF_OK);
  assert_int_equal(info.guides, 3066);
  assert_int_equal(info.vertices, 16);
  assert_float_equal(info.version, 3.0f, 0);
  assert_int_equal(satf_strand_set_point_count(s), 3066 * 16);
  satf_strand_set_destroy(s);
  snprintf(path, sizeof path, "%s/hair/Bangs_100.hair", SATF_SHARED_DATA_DIR);
  assert_int_equal(satf_hair_read(path, &s, &err), SATF_OK);
  assert_int_equal(satf_strand_set_count(s), 100);
  assert_int_equal(satf_strand_set_point_count(s), 1165);
  for (int i = 0; i < 100; i++) {
    int n = satf_strand_set_points(s, i);
    assert_true(n >= 5 && n <= 21);
  }
  satf_strand_set_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(hair_round_trip),
      cmocka_unit_test(hair_default_thickness),
      cmocka_unit_test(tfx_round_trips),
      cmocka_unit_test(hair_malformed),
      cmocka_unit_test(tfx_malformed),
      cmocka_unit_test(strand_set_rejects),
      cmocka_unit_test(follow_strands),
      cmocka_unit_test(concat_sets),
      cmocka_unit_test(fuzz_replays),
      cmocka_unit_test(real_data),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
