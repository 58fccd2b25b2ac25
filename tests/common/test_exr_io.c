/* test_exr_io.c - the OpenEXR layer: a write/read round trip, and a write
 * that fails half-way (the disk fills up) returning a clear error, leaving
 * nothing at the output path, instead of deadlocking in the error handler
 * (issue: satf-build and satf-render hung forever on a full disk). */
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
  satf_exr_write_opts opts = {EXR_PIXEL_FLOAT, EXR_COMPRESSION_ZIP, NULL, NULL};
  satf_error err;
  assert_int_equal(satf_exr_write(path, W, H, ch, 2, &opts, &err), SATF_OK);
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
  satf_exr_write_opts opts = {EXR_PIXEL_FLOAT, EXR_COMPRESSION_NONE, NULL,
                              NULL};
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
      cmocka_unit_test(test_full_disk_fails_cleanly),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
