/* test_strand_formats.c - the PLY and USC-HairSalon .data readers: round
 * trips of files the test writes (every point compared exactly), malformed
 * and truncated files rejected with their messages, format detection by
 * the bytes with misleading names, and fuzz replays of valid files. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "import_internal.h"
#include "satf/math.h"
#include "test_util.h"

int fuzz_ply_one(const uint8_t *data, size_t size);
int fuzz_data_one(const uint8_t *data, size_t size);

/* Three strands of 2, 4 and 3 points at values floats hold exactly. */
enum { N_STRANDS = 3, N_POINTS = 9 };
static const int COUNTS[N_STRANDS] = {2, 4, 3};
static float point(int k, int c) {
  return (float)(k * 3 + c) * 0.375f - 2.5f + (c == 2 ? 1024.0f : 0.0f);
}

/* s holds exactly the three strands above. */
static void expect_strands(const satf_strand_set *s) {
  assert_int_equal(satf_strand_set_count(s), N_STRANDS);
  int k = 0;
  for (int i = 0; i < N_STRANDS; i++) {
    int n;
    const float *p = satf_strand_set_strand(s, i, &n);
    assert_int_equal(n, COUNTS[i]);
    for (int j = 0; j < n; j++, k++)
      for (int c = 0; c < 3; c++)
        assert_true(p[3 * j + c] == point(k, c));
  }
}

/* Appends formatted text to buf at *len. */
static void addf(char *buf, size_t *len, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  *len += (size_t)vsnprintf(buf + *len, 8192 - *len, fmt, ap);
  va_end(ap);
}

/* An ascii PLY with colours and a strand element of vertex counts; a
 * one-point strand (skipped) comes last. */
static char *ascii_counts(size_t *len) {
  char *b = malloc(8192);
  *len = 0;
  addf(b, len,
       "ply\nformat ascii 1.0\ncomment written by a test\n"
       "element vertex %d\nproperty float x\nproperty float y\n"
       "property float z\nproperty uchar red\nproperty uchar green\n"
       "property uchar blue\nelement strand %d\nproperty int vertex_count\n"
       "end_header\n",
       N_POINTS + 1, N_STRANDS + 1);
  for (int k = 0; k <= N_POINTS; k++)
    addf(b, len, "%.9g %.9g %.9g 200 100 %d\n", (double)point(k, 0),
         (double)point(k, 1), (double)point(k, 2), k);
  for (int i = 0; i < N_STRANDS; i++)
    addf(b, len, "%d\n", COUNTS[i]);
  addf(b, len, "1\n");
  return b;
}

static void put_be_or_le(unsigned char **p, const void *v, int size, int be) {
  const unsigned char *s = v;
  for (int k = 0; k < size; k++)
    (*p)[k] = s[be ? size - 1 - k : k];
  *p += size;
}

/* A binary PLY (host order assumed little-endian, as the CI hosts are):
 * vertices with an extra float, and edges listed backwards and reversed
 * (be = 0), or a strand element of uint segment counts (be = 1). */
static unsigned char *binary_ply(int be, size_t *len) {
  unsigned char *b = calloc(1, 4096), *p = b;
  int n = snprintf((char *)b, 4096,
                   "ply\nformat %s 1.0\nelement vertex %d\n"
                   "property float x\nproperty float y\nproperty float z\n"
                   "property float confidence\n%s\nend_header\n",
                   be ? "binary_big_endian" : "binary_little_endian", N_POINTS,
                   be ? "element strand 3\nproperty uint segments"
                      : "element edge 6\nproperty int vertex1\n"
                        "property int vertex2");
  p += n;
  for (int k = 0; k < N_POINTS; k++)
    for (int c = 0; c <= 3; c++) {
      float v = c < 3 ? point(k, c) : 0.5f;
      put_be_or_le(&p, &v, 4, be);
    }
  if (be) {
    for (int i = 0; i < N_STRANDS; i++) {
      uint32_t seg = (uint32_t)COUNTS[i] - 1;
      put_be_or_le(&p, &seg, 4, be);
    }
  } else {
    /* strands 0-1, 2-3-4-5, 6-7-8 as edges in a scrambled order */
    static const int32_t e[6][2] = {{8, 7}, {3, 4}, {0, 1},
                                    {6, 7}, {2, 3}, {5, 4}};
    for (int k = 0; k < 6; k++)
      for (int j = 0; j < 2; j++)
        put_be_or_le(&p, &e[k][j], 4, be);
  }
  *len = (size_t)(p - b);
  return b;
}

/* A .data file of the strands with a one-point and an empty strand. */
static unsigned char *usc_data(size_t *len) {
  unsigned char *b = calloc(1, 4096), *p = b;
  int32_t n = N_STRANDS + 2, one = 1, zero = 0;
  put_be_or_le(&p, &n, 4, 0);
  put_be_or_le(&p, &one, 4, 0);
  float lone[3] = {9.0f, 9.0f, 9.0f};
  put_be_or_le(&p, lone, 12, 0);
  int k = 0;
  for (int i = 0; i < N_STRANDS; i++) {
    put_be_or_le(&p, &COUNTS[i], 4, 0);
    for (int j = 0; j < COUNTS[i]; j++, k++)
      for (int c = 0; c < 3; c++) {
        float v = point(k, c);
        put_be_or_le(&p, &v, 4, 0);
      }
    if (i == 0)
      put_be_or_le(&p, &zero, 4, 0);
  }
  *len = (size_t)(p - b);
  return b;
}

static void round_trips(void **state) {
  (void)state;
  char path[512];
  size_t len;
  satf_strand_set *s;
  satf_error err;
  char *a = ascii_counts(&len);
  test_write_file(test_path(path, sizeof path, "rt.ply"), a, len);
  free(a);
  assert_int_equal(satf_ply_read(path, &s, &err), SATF_OK);
  expect_strands(s);
  satf_strand_set_destroy(s);
  for (int be = 0; be < 2; be++) {
    unsigned char *b = binary_ply(be, &len);
    assert_int_equal(satf_ply_parse(b, len, "b.ply", &s, &err), SATF_OK);
    expect_strands(s);
    satf_strand_set_destroy(s);
    free(b);
  }
  unsigned char *d = usc_data(&len);
  test_write_file(test_path(path, sizeof path, "rt.data"), d, len);
  free(d);
  assert_int_equal(satf_usc_read(path, &s, &err), SATF_OK);
  expect_strands(s);
  satf_strand_set_destroy(s);
}

/* text parsed as a PLY fails with exactly `message`. */
static void ply_fails(const char *text, const char *message) {
  satf_strand_set *s = (satf_strand_set *)1;
  satf_error err;
  assert_int_not_equal(satf_ply_parse(text, strlen(text), "m.ply", &s, &err),
                       SATF_OK);
  assert_null(s);
  assert_string_equal(err.message, message);
}

static void ply_malformed(void **state) {
  (void)state;
  const char *head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty "
                     "float x\nproperty float y\nproperty float z\n";
  char t[1024];
  ply_fails("plyx", "m.ply: not a PLY file (no \"ply\" line first)");
  snprintf(t, sizeof t, "%send_header\n0 0 0 1 1 1 2 2 2\n", head);
  ply_fails(t, "m.ply: vertices but neither a strand element (strand, "
               "strands, hair, curve) nor an `edge` element: nothing says "
               "which points form a strand");
  snprintf(t, sizeof t,
           "%selement strand 1\nproperty int vertex_count\nend_header\n"
           "0 0 0 1 1 1 2 2 2\n2\n",
           head);
  ply_fails(t, "m.ply: counts do not add up: the strands need 2 points, the "
               "file has 3 vertices");
  snprintf(t, sizeof t,
           "%selement edge 3\nproperty int vertex1\nproperty int vertex2\n"
           "end_header\n0 0 0 1 1 1 2 2 2\n0 1\n1 2\n2 0\n",
           head);
  ply_fails(t, "m.ply: the edges through vertex 0 form a loop, not a strand");
  snprintf(t, sizeof t,
           "%selement edge 3\nproperty int vertex1\nproperty int vertex2\n"
           "end_header\n0 0 0 1 1 1 2 2 2\n0 1\n0 2\n0 2\n",
           head);
  ply_fails(t, "m.ply: vertex 0 has more than two edges: strands cannot "
               "branch");
  snprintf(t, sizeof t,
           "%selement edge 1\nproperty int vertex1\nproperty int vertex2\n"
           "end_header\n0 0 0 1 1 1 2 2 2\n0 7\n",
           head);
  ply_fails(t, "m.ply: edge 0 joins vertices 0 and 7 (the file has 3 "
               "vertices)");
  snprintf(t, sizeof t,
           "%selement strand 1\nproperty int count\nend_header\n"
           "0 0 0 1 1 1 2 2 nan\n3\n",
           head);
  ply_fails(t, "m.ply: vertex 2: coordinate z is not a finite float");
  snprintf(t, sizeof t, "%sproperty float w x\nend_header\n", head);
  ply_fails(t, "m.ply: header line 7: bad property \"property float w x\"");
  ply_fails("ply\nformat binary_little_endian 1.0\nelement vertex "
            "4000000000\nproperty float x\nend_header\n",
            "m.ply: truncated: the header's element counts need at least "
            "16000000000 bytes, the file has 0 after it");
  /* a binary body cut short: the count check passes, the read fails */
  size_t len;
  unsigned char *b = binary_ply(0, &len);
  satf_strand_set *s;
  satf_error err;
  assert_int_not_equal(satf_ply_parse(b, len - 30, "c.ply", &s, &err), SATF_OK);
  assert_string_equal(err.message,
                      "c.ply: truncated: the header's element counts need "
                      "at least 192 bytes, the file has 162 after it");
  free(b);
}

/* bytes parsed as .data fail with exactly `message`. */
static void usc_fails(const unsigned char *b, size_t len, const char *msg) {
  satf_strand_set *s = (satf_strand_set *)1;
  satf_error err;
  assert_int_not_equal(satf_usc_parse(b, len, "m.data", &s, &err), SATF_OK);
  assert_null(s);
  assert_string_equal(err.message, msg);
}

static void usc_malformed(void **state) {
  (void)state;
  size_t len;
  unsigned char *d = usc_data(&len);
  usc_fails(d, 3, "m.data: truncated: 3 bytes, not even a strand count");
  usc_fails(d, len - 1,
            "m.data: truncated: strand 4 needs 3 points, 35 "
            "bytes are left");
  unsigned char *more = calloc(1, len + 8);
  memcpy(more, d, len);
  usc_fails(more, len + 8, "m.data: 8 bytes after the last of its 5 strands");
  memcpy(more, "\xff\xff\xff\x7f", 4);
  usc_fails(more, len, "m.data: absurd strand count 2147483647 for 144 bytes");
  memcpy(more, "\x01\0\0\0\x01\0\0\0", 8);
  usc_fails(more, 20, "m.data: holds no strand of two or more points");
  free(more);
  free(d);
}

/* Files named for another format are called by what they are. */
static void detection(void **state) {
  (void)state;
  char path[512];
  size_t len;
  satf_import_options o = satf_import_options_default();
  satf_strand_set *s;
  satf_error err;
  char *a = ascii_counts(&len);
  assert_int_equal(satf_strands_detect(a, len), SATF_STRANDS_PLY);
  test_write_file(test_path(path, sizeof path, "ply-named.tfx"), a, len);
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err),
                   SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message, "ply-named.tfx: this is a PLY file, "
                                      "not TressFX (rename it to end in "
                                      ".ply)"));
  /* a name that says nothing: the bytes decide */
  test_write_file(test_path(path, sizeof path, "strands.bin"), a, len);
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), SATF_OK);
  expect_strands(s);
  satf_strand_set_destroy(s);
  free(a);
  unsigned char *d = usc_data(&len);
  assert_int_equal(satf_strands_detect(d, len), SATF_STRANDS_USC);
  assert_int_equal(satf_strands_detect(d, len - 1), SATF_STRANDS_UNKNOWN);
  test_write_file(test_path(path, sizeof path, "data-named.hair"), d, len);
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err),
                   SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message,
                         "data-named.hair: this is a USC-HairSalon .data "
                         "file, not cyHair (rename it to end in .data)"));
  test_write_file(test_path(path, sizeof path, "usc.data"), d, len);
  assert_int_equal(satf_import_read_strands(path, &o, &s, &err), SATF_OK);
  expect_strands(s);
  satf_strand_set_destroy(s);
  free(d);
  assert_int_equal(satf_strands_detect("HAIR", 4), SATF_STRANDS_HAIR);
  assert_string_equal(satf_strands_format_name(SATF_STRANDS_USC),
                      "USC-HairSalon .data");
}

static void fuzz_replays(void **state) {
  (void)state;
  size_t len;
  char *a = ascii_counts(&len);
  test_replay_mutations(fuzz_ply_one, (unsigned char *)a, len);
  free(a);
  for (int be = 0; be < 2; be++) {
    unsigned char *b = binary_ply(be, &len);
    test_replay_mutations(fuzz_ply_one, b, len);
    free(b);
  }
  unsigned char *d = usc_data(&len);
  test_replay_mutations(fuzz_data_one, d, len);
  free(d);
}

/* 64 strands of 16 points hanging from an 8 x 8 grid, all points times
 * scale plus offset, point 7 of strand 5 replaced by `odd` when finite;
 * helix > 0 winds them that many turns about the grid's centre instead,
 * with 65536 points each. Written as a .hair file at path. */
static void write_hair(const char *path, double scale, double offset, float odd,
                       double helix) {
  int n = helix > 0 ? 8 : 64, m = helix > 0 ? SATF_STRANDS_MAX_PER_STRAND : 16;
  int *counts = malloc((size_t)n * sizeof(int));
  float *p = malloc((size_t)n * (size_t)m * 3 * sizeof(float));
  assert_non_null(counts);
  assert_non_null(p);
  for (int i = 0; i < n; i++) {
    counts[i] = m;
    double x0 = 0.1 * (i % 8) - 0.35, y0 = 0.1 * (i / 8) - 0.35;
    if (helix > 0) { /* a ring of strands winding about its axis */
      x0 = 0.2 * cos(SATF_TWO_PI * i / n);
      y0 = 0.2 * sin(SATF_TWO_PI * i / n);
    }
    for (int j = 0; j < m; j++) {
      double t = (double)j / (m - 1),
             q[3] = {x0 + 0.05 * sin(6 * t), y0, -2.0 * t};
      if (helix > 0) {
        double r = sqrt(x0 * x0 + y0 * y0), a0 = atan2(y0, x0);
        double a = a0 + SATF_TWO_PI * helix * t;
        q[0] = r * cos(a);
        q[1] = r * sin(a);
      }
      for (int c = 0; c < 3; c++)
        p[3 * ((size_t)i * (size_t)m + (size_t)j) + (size_t)c] =
            (float)(q[c] * scale + offset);
    }
  }
  if (isfinite(odd))
    p[3 * (5 * m + 7)] = odd;
  satf_strand_set *s;
  satf_error err;
  assert_int_equal(satf_strand_set_create(n, counts, p, NULL, &s, &err),
                   SATF_OK);
  assert_int_equal(satf_hair_write(path, s, &err), SATF_OK);
  satf_strand_set_destroy(s);
  free(counts);
  free(p);
}

/* Imports `name` (written by write_hair) into NAME.json; returns the
 * status, with the result and message. The scene must load when written
 * and must not exist otherwise. */
static satf_status import_one(const char *name, satf_import_result *r,
                              satf_error *err) {
  char in[512], out[1024], json[256];
  test_path(in, sizeof in, name);
  snprintf(json, sizeof json, "%s.json", name);
  test_path(out, sizeof out, json);
  remove(out);
  satf_import_options o = satf_import_options_default();
  o.inputs[0] = in;
  o.n_inputs = 1;
  o.output = out;
  o.quiet = 1;
  o.clusters = 4;
  satf_status st = satf_import_run(&o, r, err);
  FILE *f = fopen(out, "rb");
  if (st != SATF_OK) {
    assert_null(f);
  } else {
    assert_non_null(f);
    fclose(f);
    satf_scene *scene;
    satf_error why;
    assert_int_equal(satf_scene_load(out, &scene, &why), SATF_OK);
    satf_scene_destroy(scene);
  }
  return st;
}

/* Hair in tiny or huge units is rescaled by a power of ten to span 1-10
 * units; hair no scale can save, or whose fit breaks a scene limit, is
 * refused with nothing written. */
static void import_limits(void **state) {
  (void)state;
  char path[512];
  satf_import_result r;
  satf_error err;
  write_hair(test_path(path, sizeof path, "fmt-units.hair"), 1.0, 0.0, NAN, 0);
  assert_int_equal(import_one("fmt-units.hair", &r, &err), SATF_OK);
  assert_true(r.scale == 1.0);
  write_hair(test_path(path, sizeof path, "fmt-tiny.hair"), 1e-40, 0.0, NAN, 0);
  assert_int_equal(import_one("fmt-tiny.hair", &r, &err), SATF_OK);
  assert_true(r.scale == 1e40);
  write_hair(test_path(path, sizeof path, "fmt-huge.hair"), 1e7, 0.0, NAN, 0);
  assert_int_equal(import_one("fmt-huge.hair", &r, &err), SATF_OK);
  assert_true(r.scale == 1e-7);
  /* 1e30 would rescale, but no unit puts hair there: refused, naming the
   * point; 1e14 is within the bound and rescales */
  write_hair(test_path(path, sizeof path, "fmt-1e30.hair"), 1e30, 0.0, NAN, 0);
  assert_int_not_equal(import_one("fmt-1e30.hair", &r, &err), SATF_OK);
  print_message("1e30: %s\n", err.message);
  assert_non_null(strstr(err.message, "fmt-1e30.hair: strand 0 point "));
  assert_non_null(strstr(err.message, "beyond the 1e+15 an input may hold"));
  write_hair(test_path(path, sizeof path, "fmt-1e14.hair"), 1e14, 0.0, NAN, 0);
  assert_int_equal(import_one("fmt-1e14.hair", &r, &err), SATF_OK);
  assert_true(r.scale == 1e-14);
  write_hair(test_path(path, sizeof path, "fmt-far.hair"), 1.0, 1e6, NAN, 0);
  assert_int_not_equal(import_one("fmt-far.hair", &r, &err), SATF_OK);
  print_message("far: %s\n", err.message);
  assert_non_null(strstr(err.message, "fmt-far.hair: the hair spans "));
  assert_non_null(strstr(err.message, "no scale brings it within the scene "
                                      "limits (coordinates up to 100000"));
  write_hair(test_path(path, sizeof path, "fmt-flip.hair"), 1.0, 0.0, 3e30f, 0);
  assert_int_not_equal(import_one("fmt-flip.hair", &r, &err), SATF_OK);
  assert_non_null(strstr(err.message, "fmt-flip.hair: "));
  print_message("flip: %s\n", err.message);
  write_hair(test_path(path, sizeof path, "fmt-twist.hair"), 1.0, 0.0, NAN,
             2500);
  assert_int_not_equal(import_one("fmt-twist.hair", &r, &err), SATF_OK);
  print_message("twist: %s\n", err.message);
  assert_non_null(strstr(err.message, "fmt-twist.hair: the scene made from it "
                                      "breaks the scene limits"));
}

/* The command-line tests' inputs: the 64 hanging strands as an ascii PLY
 * with an edge element (fmt-cli.ply), as .data (fmt-cli.data) and as a
 * PLY named .tfx (fmt-cli-ply.tfx). */
static void cli_inputs(void **state) {
  (void)state;
  char path[512];
  satf_strand_set *s;
  satf_error err;
  write_hair(test_path(path, sizeof path, "fmt-cli.hair"), 1.0, 0.0, NAN, 0);
  assert_int_equal(satf_hair_read(path, &s, &err), SATF_OK);
  int n = satf_strand_set_count(s);
  size_t np = satf_strand_set_point_count(s), len = 0, dlen = 0;
  char *ply = malloc(64 * np + 256);
  unsigned char *d = malloc(4 + 4 * (size_t)n + 12 * np), *q = d;
  len += (size_t)sprintf(ply,
                         "ply\nformat ascii 1.0\nelement vertex %zu\n"
                         "property float x\nproperty float y\nproperty "
                         "float z\nelement edge %zu\nproperty int "
                         "vertex1\nproperty int vertex2\nend_header\n",
                         np, np - (size_t)n);
  put_be_or_le(&q, &n, 4, 0);
  for (int i = 0; i < n; i++) {
    int m;
    const float *p = satf_strand_set_strand(s, i, &m);
    put_be_or_le(&q, &m, 4, 0);
    for (int j = 0; j < m; j++) {
      len += (size_t)sprintf(ply + len, "%.9g %.9g %.9g\n", (double)p[3 * j],
                             (double)p[3 * j + 1], (double)p[3 * j + 2]);
      put_be_or_le(&q, p + 3 * j, 12, 0);
    }
  }
  for (int i = 0, at = 0; i < n; i++, at++)
    for (int j = 1; j < satf_strand_set_points(s, i); j++, at++)
      len += (size_t)sprintf(ply + len, "%d %d\n", at, at + 1);
  dlen = (size_t)(q - d);
  test_write_file(test_path(path, sizeof path, "fmt-cli.ply"), ply, len);
  test_write_file(test_path(path, sizeof path, "fmt-cli-ply.tfx"), ply, len);
  test_write_file(test_path(path, sizeof path, "fmt-cli.data"), d, dlen);
  satf_strand_set *back;
  assert_int_equal(
      satf_ply_read(test_path(path, sizeof path, "fmt-cli.ply"), &back, &err),
      SATF_OK);
  assert_int_equal(satf_strand_set_count(back), n);
  assert_int_equal(satf_strand_set_point_count(back), np);
  satf_strand_set_destroy(back);
  satf_strand_set_destroy(s);
  free(ply);
  free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trips),   cmocka_unit_test(ply_malformed),
      cmocka_unit_test(usc_malformed), cmocka_unit_test(detection),
      cmocka_unit_test(fuzz_replays),  cmocka_unit_test(import_limits),
      cmocka_unit_test(cli_inputs)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
