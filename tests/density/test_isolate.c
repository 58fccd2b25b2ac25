/* test_isolate.c - the child-process reader (online/density/isolate.c):
 * records handed over in order, a crash and a hang reported with the file's
 * name, and a child that stalls before its first record (a lock held by
 * another thread at the fork) started once more. Each child counts its
 * start in a file, since a child's memory is its own. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "isolate.h"

typedef enum behaviour {
  SEND_THREE,         /* three records, then success */
  CRASH,              /* SIGSEGV */
  HANG_ALWAYS,        /* sleeps past its limit every time */
  HANG_FIRST_TIME,    /* sleeps past its limit on its first start only */
  HANG_AFTER_A_RECORD /* one record, then sleeps past its limit */
} behaviour;

typedef struct job {
  behaviour what;
  char starts[512]; /* a file that gains one byte at each child's start */
} job;

typedef struct got {
  int records, sum;
} got;

static void starts_path(job *j, const char *name) {
  const char *dir = getenv("SATF_TEST_TMP");
  snprintf(j->starts, sizeof j->starts, "%s/%s", dir ? dir : ".", name);
  unlink(j->starts);
}

static long starts_of(const job *j) {
  struct stat st;
  return stat(j->starts, &st) == 0 ? (long)st.st_size : 0;
}

/* Counts its start; returns 1 for the first child of this job. */
static int count_start(const job *j) {
  const long before = starts_of(j);
  const int fd = open(j->starts, O_WRONLY | O_APPEND | O_CREAT, 0600);
  if (fd >= 0) {
    (void)!write(fd, "x", 1);
    close(fd);
  }
  return before == 0;
}

static void sleep_long(void) {
  for (;;)
    pause(); /* until the alarm */
}

static satf_status child(void *ctx, int fd, satf_error *err) {
  const job *j = ctx;
  const int first = count_start(j);
  switch (j->what) {
  case SEND_THREE:
    for (int i = 1; i <= 3; ++i)
      if (satf_isolated_send(fd, i, &i, sizeof i) != 0)
        return satf_error_set(err, SATF_ERR_IO, "send");
    return SATF_OK;
  case CRASH: raise(SIGSEGV); return SATF_OK;
  case HANG_ALWAYS: sleep_long(); return SATF_OK;
  case HANG_FIRST_TIME: {
    if (first)
      sleep_long();
    const int v = 7;
    return satf_isolated_send(fd, 1, &v, sizeof v) == 0
               ? SATF_OK
               : satf_error_set(err, SATF_ERR_IO, "send");
  }
  case HANG_AFTER_A_RECORD: {
    const int v = 5;
    if (satf_isolated_send(fd, 1, &v, sizeof v) != 0)
      return satf_error_set(err, SATF_ERR_IO, "send");
    /* The record sits in the child's buffer until a flush: sleep with it
     * still there would look like a stall, so end the record first by
     * sending a large one that forces the buffer out. */
    static unsigned char big[SATF_ISOLATED_MAX_RECORD];
    for (int i = 0; i < 9; ++i)
      satf_isolated_send(fd, 9, big, sizeof big);
    sleep_long();
    return SATF_OK;
  }
  }
  return SATF_OK;
}

static satf_status recv(void *ctx, int tag, const void *data, size_t size,
                        satf_error *err) {
  got *g = ctx;
  if (tag == 9) /* filler */
    return SATF_OK;
  if (size != sizeof(int))
    return satf_error_set(err, SATF_ERR_CORRUPT, "bad size %zu", size);
  int v;
  memcpy(&v, data, sizeof v);
  g->records++;
  g->sum += 10 * tag + v;
  return SATF_OK;
}

static double now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static satf_status run(job *j, got *g, double *seconds, satf_error *err) {
  memset(g, 0, sizeof *g);
  const double t0 = now();
  const satf_status st =
      satf_isolated_run(child, j, recv, g, "hair.vdb", "VDB file", 1, err);
  *seconds = now() - t0;
  return st;
}

static void test_records_in_order(void **state) {
  (void)state;
  job j = {SEND_THREE, ""};
  starts_path(&j, "isolate_three");
  got g;
  double s;
  satf_error err;
  assert_int_equal(run(&j, &g, &s, &err), SATF_OK);
  assert_int_equal(g.records, 3);
  assert_int_equal(g.sum, 11 + 22 + 33);
  assert_int_equal(starts_of(&j), 1);
}

static void test_crash_is_reported_once(void **state) {
  (void)state;
  job j = {CRASH, ""};
  starts_path(&j, "isolate_crash");
  got g;
  double s;
  satf_error err;
  assert_int_equal(run(&j, &g, &s, &err), SATF_ERR_CORRUPT);
  assert_string_equal(err.message,
                      "hair.vdb: damaged VDB file: the reader crashed "
                      "(SIGSEGV)");
  assert_int_equal(starts_of(&j), 1);
}

static void test_hang_is_reported_after_a_second_try(void **state) {
  (void)state;
  job j = {HANG_ALWAYS, ""};
  starts_path(&j, "isolate_hang");
  got g;
  double s;
  satf_error err;
  assert_int_equal(run(&j, &g, &s, &err), SATF_ERR_CORRUPT);
  assert_string_equal(err.message, "hair.vdb: damaged VDB file: the reader "
                                   "did not finish within 1 s");
  assert_int_equal(starts_of(&j), 2);
  assert_true(s >= 1.9 && s < 10.0);
}

static void test_stall_before_first_record_is_retried(void **state) {
  (void)state;
  job j = {HANG_FIRST_TIME, ""};
  starts_path(&j, "isolate_stall");
  got g;
  double s;
  satf_error err;
  assert_int_equal(run(&j, &g, &s, &err), SATF_OK);
  assert_int_equal(g.records, 1);
  assert_int_equal(g.sum, 17);
  assert_int_equal(starts_of(&j), 2);
}

/* A child that already handed over records may have changed recv's context,
 * so it is not started again. */
static void test_hang_after_a_record_is_not_retried(void **state) {
  (void)state;
  job j = {HANG_AFTER_A_RECORD, ""};
  starts_path(&j, "isolate_hang_late");
  got g;
  double s;
  satf_error err;
  assert_int_equal(run(&j, &g, &s, &err), SATF_ERR_CORRUPT);
  assert_non_null(strstr(err.message, "did not finish within 1 s"));
  assert_int_equal(g.records, 1);
  assert_int_equal(starts_of(&j), 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_records_in_order),
      cmocka_unit_test(test_crash_is_reported_once),
      cmocka_unit_test(test_hang_is_reported_after_a_second_try),
      cmocka_unit_test(test_stall_before_first_record_is_retried),
      cmocka_unit_test(test_hang_after_a_record_is_not_retried),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
