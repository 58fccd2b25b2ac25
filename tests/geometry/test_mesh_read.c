/* test_mesh_read.c - meshes given by users (heads, bodies): a valid OBJ
 * and PLY load with every face; garbage, empty files, dropped faces and
 * special files are refused with a message naming the file. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "satf/geometry.h"
#include "test_util.h"

static const char *write_text(char *buf, size_t size, const char *name,
                              const char *text) {
  test_path(buf, size, name);
  test_write_file(buf, text, strlen(text));
  return buf;
}

#define PLY_HEADER(faces)                                                      \
  "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"                \
  "property float y\nproperty float z\nelement face " faces "\n"               \
  "property list uchar int vertex_indices\nend_header\n"                       \
  "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"

static void expect_refused(const char *path, satf_status status,
                           const char *needle) {
  satf_mesh *m = (satf_mesh *)&m;
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_mesh_read(path, &m, &err), status);
  assert_null(m);
  assert_non_null(strstr(err.message, path));
  if (!strstr(err.message, needle))
    fail_msg("'%s' does not say '%s'", err.message, needle);
}

static void test_valid_meshes_load_every_face(void **state) {
  (void)state;
  char p[512];
  const char *files[2][2] = {
      {"ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n"
                 "f 1 4 3\nf 2 3 4\n"},
      {"ok.ply", PLY_HEADER("4") "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"}};
  for (int i = 0; i < 2; i++) {
    satf_mesh *m = NULL;
    satf_error err;
    write_text(p, sizeof p, files[i][0], files[i][1]);
    assert_int_equal(satf_mesh_read(p, &m, &err), SATF_OK);
    assert_int_equal(satf_mesh_triangle_count(m), 4);
    assert_int_equal(satf_mesh_vertex_count(m), 4);
    satf_mesh_destroy(m);
  }
}

static void test_garbage_is_refused(void **state) {
  (void)state;
  char p[512];
  expect_refused(write_text(p, sizeof p, "empty.obj", ""), SATF_ERR_FORMAT,
                 "no faces");
  unsigned char noise[4096];
  uint32_t x = 12345;
  for (size_t i = 0; i < sizeof noise; i++) {
    x = x * 1664525u + 1013904223u;
    noise[i] = (unsigned char)(x >> 24);
  }
  test_path(p, sizeof p, "noise.obj");
  test_write_file(p, noise, sizeof noise);
  expect_refused(p, SATF_ERR_FORMAT, "no faces");
  /* the second face names vertex 7 of 4 */
  expect_refused(
      write_text(p, sizeof p, "bad.ply", PLY_HEADER("2") "3 0 1 2\n3 0 1 7\n"),
      SATF_ERR_CORRUPT, "1 of 2 faces could not be used");
  expect_refused(write_text(p, sizeof p, "bad.obj",
                            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"),
                 SATF_ERR_CORRUPT, "1 of 2 faces could not be used");
}

static void test_special_files_are_refused(void **state) {
  (void)state;
  char p[512];
  test_path(p, sizeof p, "fifo.obj");
  remove(p);
  assert_int_equal(mkfifo(p, 0600), 0);
  expect_refused(p, SATF_ERR_IO, "not a regular file");
  test_path(p, sizeof p, "no-such.ply");
  expect_refused(p, SATF_ERR_IO, "cannot open");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_valid_meshes_load_every_face),
      cmocka_unit_test(test_garbage_is_refused),
      cmocka_unit_test(test_special_files_are_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
