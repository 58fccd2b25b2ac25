/* test_util.h - small helpers shared by the cmocka tests: scratch paths,
 * whole-file reading and writing, a tolerance assertion that prints the
 * expression, and float 3-vector measures evaluated in double precision. */
#ifndef SATF_TESTS_TEST_UTIL_H
#define SATF_TESTS_TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A path under the test's scratch directory ($SATF_TEST_TMP or /tmp). */
static inline const char *test_path(char *buf, size_t size, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(buf, size, "%s/%s", dir && *dir ? dir : "/tmp", name);
  return buf;
}

/* The whole file (malloc'd, caller frees, NUL-terminated after *size
 * bytes); fails the test if unreadable. */
static inline unsigned char *test_read_file(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  assert_true(n >= 0);
  unsigned char *buf = malloc((size_t)n + 1);
  assert_non_null(buf);
  assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
  fclose(f);
  buf[n] = '\0';
  *size = (size_t)n;
  return buf;
}

/* Writes size bytes to path; fails the test on error. */
static inline void test_write_file(const char *path, const void *data,
                                   size_t size) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, size, f), size);
  assert_int_equal(fclose(f), 0);
}

/* Feeds a fuzz entry point every truncation of a valid file and 4000
 * copies with 1-3 flipped bits (a fixed LCG, so every run is the same);
 * the entry point aborts on a silent failure or a broken result. */
static inline void test_replay_mutations(int (*one)(const uint8_t *, size_t),
                                         const unsigned char *b, size_t size) {
  for (size_t n = 0; n <= size; n++)
    one(b, n);
  unsigned char *c = malloc(size);
  assert_non_null(c);
  uint32_t x = 12345;
  for (int k = 0; k < 4000; k++) {
    memcpy(c, b, size);
    for (int f = 0; f < 1 + k % 3; f++) {
      x = x * 1664525u + 1013904223u;
      size_t at = (x >> 8) % size;
      x = x * 1664525u + 1013904223u;
      c[at] ^= (unsigned char)(1u << (x >> 29));
    }
    one(c, size);
  }
  free(c);
}

/* assert_near(a, b, tol): |a - b| <= tol, printing the expression. */
#define assert_near(a, b, tol) test_near_at((a), (b), (tol), #a, __LINE__)
static inline void test_near_at(double a, double b, double tol,
                                const char *expr, int line) {
  if (!(fabs(a - b) <= tol)) {
    print_error("line %d: %s = %.9g, expected %.9g +- %.3g\n", line, expr, a, b,
                tol);
    fail();
  }
}

/* Float 3-vectors measured in double precision. */
static inline double test_dot3(const float a[3], const float b[3]) {
  return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}
static inline double test_len3(const float a[3]) {
  return sqrt(test_dot3(a, a));
}
static inline void test_sub3(const float a[3], const float b[3], float out[3]) {
  for (int c = 0; c < 3; c++)
    out[c] = a[c] - b[c];
}

#endif
