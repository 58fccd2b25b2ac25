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
