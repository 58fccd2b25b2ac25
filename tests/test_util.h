/* test_util.h - small helpers shared by the cmocka tests. */
#ifndef SATF_TESTS_TEST_UTIL_H
#define SATF_TESTS_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>

/* A path under the test's scratch directory ($SATF_TEST_TMP or /tmp). */
static inline const char *test_path(char *buf, size_t size, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(buf, size, "%s/%s", dir && *dir ? dir : "/tmp", name);
  return buf;
}

#endif
