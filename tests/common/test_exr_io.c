/* test_exr_io.c - the OpenEXR layer: a write/read round trip, and a write
 * that fails half-way (the disk fills up) returning a clear error, leaving
 * nothing at the output path, instead of deadlocking in the error handler
 * (which once hung satf-build and satf-render on a full disk). */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <glob.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "satf/common.h"
#include "test_util.h"

enum { W = 64, H = 48 };

static void fill(float *a, float *b) {
  for (int i = 0; i < W * H; i++) {
    a[i] = (float)(i % 97) / 97.0f;
    b[i] = (float)((i * 7) % 31) - 15.0f;
  }
}

static void test_round_trip(void **state) {
  (void)state;
  static float a[W * H], b[W * H];
  fill(a, b);
  char path[512];
  test_path(path, sizeof path, "exr_round_trip.exr");
  satf_exr_channel ch[2] = {{"A", a}, {"B", b}};
  satf_exr_write_opts opts = {EXR_PIXEL_FLOAT, EXR_COMPRESSION_ZIP, NULL, NULL,
                              0};
  satf_error err;
  satf_status wst = satf_exr_write(path, W, H, ch, 2, &opts, &err);
  if (wst != SATF_OK)
    fail_msg("%s", err.message);
  const char *names[2] = {"B", "A"};
  float *planes[2];
  int w = 0, h = 0;
  assert_int_equal(
      satf_exr_read(path, names, 2, 1 << 20, NULL, NULL, &w, &h, planes, &err),
      SATF_OK);
  assert_int_equal(w, W);
  assert_int_equal(h, H);
  assert_memory_equal(planes[0], b, sizeof b);
  assert_memory_equal(planes[1], a, sizeof a);
  free(planes[0]);
  free(planes[1]);
  /* a channel that is not there is named */
  const char *missing[1] = {"Z"};
  assert_int_equal(satf_exr_read(path, missing, 1, 1 << 20, NULL, NULL, &w, &h,
                                 planes, &err),
                   SATF_ERR_FORMAT);
  assert_non_null(strstr(err.message, "channel 'Z' is missing"));
  assert_null(planes[0]);
}

/* Chunks compressed on several threads (write_chunks): a tall image of 63
 * ZIP chunks, two batches and a short last chunk, gives the same file on
 * 1, 2 and 3 threads, and reads back exactly. */
static void test_threads_same_file(void **state) {
  (void)state;
  enum { TW = 40, TH = 1000 };
  static float a[TW * TH];
  for (int i = 0; i < TW * TH; i++)
    a[i] = (float)((i * 2654435761u) % 1000u) / 7.0f;
  satf_exr_channel ch[1] = {{"Y", a}};
  char path[3][512];
  const char *names[3] = {"exr_threads_1.exr", "exr_threads_2.exr",
                          "exr_threads_3.exr"};
  satf_error err;
  for (int t = 0; t < 3; t++) {
    test_path(path[t], sizeof path[t], names[t]);
    satf_exr_write_opts opts = {EXR_PIXEL_FLOAT, EXR_COMPRESSION_ZIP, NULL,
                                NULL, t + 1};
    assert_int_equal(satf_exr_write(path[t], TW, TH, ch, 1, &opts, &err),
                     SATF_OK);
  }
  size_t n[3];
  unsigned char *bytes[3];
  for (int t = 0; t < 3; t++) {
    FILE *f = fopen(path[t], "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    n[t] = (size_t)ftell(f);
    rewind(f);
    bytes[t] = malloc(n[t]);
    assert_non_null(bytes[t]);
    assert_int_equal(fread(bytes[t], 1, n[t], f), n[t]);
    fclose(f);
  }
  for (int t = 1; t < 3; t++) {
    assert_int_equal(n[t], n[0]);
    assert_memory_equal(bytes[t], bytes[0], n[0]);
  }
  const char *y[1] = {"Y"};
  float *plane[1];
  int w = 0, h = 0;
  assert_int_equal(
      satf_exr_read(path[1], y, 1, 1 << 20, NULL, NULL, &w, &h, plane, &err),
      SATF_OK);
  assert_int_equal(h, TH);
  assert_memory_equal(plane[0], a, sizeof a);
  free(plane[0]);
  for (int t = 0; t < 3; t++) {
    free(bytes[t]);
    remove(path[t]);
  }
}

/* In a child whose files may not grow past `limit` bytes (RLIMIT_FSIZE with
 * SIGXFSZ ignored: write() then fails as on a full disk), writes an image
 * far larger than that. Exit status: 0 a clean SATF_ERR_IO with nothing left at
 * path, 2 any other outcome; an alarm kills a deadlocked child. */
static void write_into_full_disk(const char *path, rlim_t limit) {
  struct rlimit lim = {limit, limit};
  signal(SIGXFSZ, SIG_IGN);
  alarm(20);
  if (setrlimit(RLIMIT_FSIZE, &lim) != 0)
    _exit(3);
  static float noise[512 * 512];
  for (int i = 0; i < 512 * 512; i++)
    noise[i] = (float)((i * 2654435761u) % 1000003u);
  satf_exr_channel ch[1] = {{"Y", noise}};
  satf_exr_write_opts opts = {EXR_PIXEL_FLOAT, EXR_COMPRESSION_NONE, NULL, NULL,
                              0};
  satf_error err;
  satf_status st = satf_exr_write(path, 512, 512, ch, 1, &opts, &err);
  struct stat sb;
  int clean = st == SATF_ERR_IO && strstr(err.message, "cannot write") &&
              stat(path, &sb) != 0;
  if (!clean)
    fprintf(stderr, "status %d: %s\n", (int)st, err.message);
  _exit(clean ? 0 : 2);
}

/* The disk fills up at `limit` bytes: inside the header (the handler used
 * to deadlock there) or among the pixel chunks. */
static void full_disk_at(rlim_t limit) {
  char path[512];
  test_path(path, sizeof path, "exr_full_disk.exr");
  remove(path);
  fflush(NULL);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0)
    write_into_full_disk(path, limit);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  if (WIFSIGNALED(status))
    fail_msg("the writer was killed by signal %d (deadlock: SIGALRM is 14)",
             WTERMSIG(status));
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 0);
  /* and its temporary file is gone too */
  char pattern[600];
  snprintf(pattern, sizeof pattern, "%s.tmp-*", path);
  glob_t g;
  assert_int_equal(glob(pattern, 0, NULL, &g), GLOB_NOMATCH);
}

static void test_full_disk_fails_cleanly(void **state) {
  (void)state;
  full_disk_at(16);
  full_disk_at(4096);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip),
      cmocka_unit_test(test_threads_same_file),
      cmocka_unit_test(test_full_disk_fails_cleanly),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
