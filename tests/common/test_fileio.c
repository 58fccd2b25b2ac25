/* test_fileio.c - capped whole-file reading and the temp-file-and-rename
 * writer: exact limits, exact messages, and no half-written or stray files
 * left behind. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "satf/common.h"
#include "test_util.h"

/* A fresh, empty scratch directory for one test. */
static const char *scratch(char *buf, size_t size, const char *name) {
  char dir[512];
  test_path(dir, sizeof dir, "common_fileio");
  mkdir(dir, 0755);
  snprintf(buf, size, "%s/%s", dir, name);
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", buf);
  assert_int_equal(system(cmd), 0);
  assert_int_equal(mkdir(buf, 0755), 0);
  return buf;
}

static void put(const char *path, const void *data, size_t size) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, size, f), size);
  assert_int_equal(fclose(f), 0);
}

/* Number of entries in dir (without . and ..), and how many hold ".tmp-". */
static int entries(const char *dir, int *temps) {
  DIR *d = opendir(dir);
  assert_non_null(d);
  int n = 0;
  *temps = 0;
  struct dirent *e;
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
      continue;
    n++;
    if (strstr(e->d_name, ".tmp-"))
      (*temps)++;
  }
  closedir(d);
  return n;
}

static void read_file_returns_content_up_to_the_exact_cap(void **state) {
  (void)state;
  char dir[600], path[700];
  scratch(dir, sizeof dir, "cap");
  snprintf(path, sizeof path, "%s/hundred.bin", dir);
  unsigned char bytes[100];
  for (int i = 0; i < 100; i++)
    bytes[i] = (unsigned char)(i * 7 + 1);
  put(path, bytes, sizeof bytes);

  void *data = NULL;
  size_t size = 0;
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_read_file(path, 100, &data, &size, &err), SATF_OK);
  assert_int_equal(size, 100);
  assert_memory_equal(data, bytes, 100);
  assert_int_equal(((unsigned char *)data)[100], 0); /* NUL after the end */
  free(data);

  data = (void *)1;
  size = 5;
  assert_int_equal(satf_read_file(path, 99, &data, &size, &err), SATF_ERR_IO);
  assert_null(data);
  assert_int_equal(size, 0);
  char expect[800];
  snprintf(expect, sizeof expect, "%s: 100 bytes is over the limit of 99 bytes",
           path);
  assert_string_equal(err.message, expect);
}

static void read_file_of_an_empty_file(void **state) {
  (void)state;
  char dir[600], path[700];
  scratch(dir, sizeof dir, "empty");
  snprintf(path, sizeof path, "%s/empty.txt", dir);
  put(path, "", 0);
  void *data = NULL;
  size_t size = 9;
  assert_int_equal(satf_read_file(path, 0, &data, &size, NULL), SATF_OK);
  assert_non_null(data); /* a valid, empty string */
  assert_int_equal(size, 0);
  assert_string_equal((const char *)data, "");
  free(data);
}

static void read_file_names_the_missing_file(void **state) {
  (void)state;
  char dir[600], path[700];
  scratch(dir, sizeof dir, "missing");
  snprintf(path, sizeof path, "%s/no-such.hair", dir);
  void *data = (void *)1;
  size_t size = 3;
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_read_file(path, 1 << 20, &data, &size, &err),
                   SATF_ERR_IO);
  assert_null(data);
  assert_int_equal(size, 0);
  char expect[800];
  snprintf(expect, sizeof expect, "%s: cannot open: %s", path,
           strerror(ENOENT));
  assert_string_equal(err.message, expect);
}

static void read_file_refuses_a_directory(void **state) {
  (void)state;
  char dir[600];
  scratch(dir, sizeof dir, "directory");
  void *data = (void *)1;
  size_t size = 3;
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_read_file(dir, SIZE_MAX, &data, &size, &err),
                   SATF_ERR_IO);
  assert_null(data);
  assert_int_equal(size, 0);
  char expect[800];
  snprintf(expect, sizeof expect, "%s: not a regular file", dir);
  assert_string_equal(err.message, expect);
}

/* /proc files claim 0 bytes but hold more: reading exactly the claimed size
 * would silently truncate them, so the reader must fail instead. */
static void read_file_never_returns_a_truncated_file(void **state) {
  (void)state;
  struct stat st;
  if (stat("/proc/self/status", &st) != 0 || st.st_size != 0)
    skip();
  void *data = (void *)1;
  size_t size = 3;
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(
      satf_read_file("/proc/self/status", 1 << 20, &data, &size, &err),
      SATF_ERR_IO);
  assert_null(data);
  assert_int_equal(size, 0);
  assert_string_equal(err.message,
                      "/proc/self/status: changed size while being read");
}

static void atomic_write_replaces_content_and_leaves_no_temp(void **state) {
  (void)state;
  char dir[600], path[700];
  scratch(dir, sizeof dir, "atomic");
  snprintf(path, sizeof path, "%s/out.json", dir);
  satf_error err;
  satf_error_clear(&err);
  const char first[] = "{\"version\": 1, \"long\": \"first and longer\"}";
  assert_int_equal(satf_write_file_atomic(path, first, strlen(first), &err),
                   SATF_OK);
  const char second[] = "{\"version\": 2}";
  assert_int_equal(satf_write_file_atomic(path, second, strlen(second), &err),
                   SATF_OK);
  void *data = NULL;
  size_t size = 0;
  assert_int_equal(satf_read_file(path, 1 << 20, &data, &size, &err), SATF_OK);
  assert_int_equal(size, strlen(second)); /* no tail of the longer first */
  assert_string_equal((const char *)data, second);
  free(data);
  assert_int_equal(satf_file_size(path), (long long)strlen(second));
  int temps;
  assert_int_equal(entries(dir, &temps), 1);
  assert_int_equal(temps, 0);
}

static void atomic_write_into_a_missing_directory_fails_cleanly(void **state) {
  (void)state;
  char dir[600], path[800];
  scratch(dir, sizeof dir, "nodir");
  snprintf(path, sizeof path, "%s/absent/out.bin", dir);
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_write_file_atomic(path, "abc", 3, &err), SATF_ERR_IO);
  char expect[1800];
  snprintf(expect, sizeof expect, "%s: cannot create %s.tmp-%ld: %s", path,
           path, (long)getpid(), strerror(ENOENT));
  assert_string_equal(err.message, expect);
  int temps;
  assert_int_equal(entries(dir, &temps), 0); /* nothing created anywhere */
  assert_int_equal(satf_file_size(path), -1);
}

static void temp_path_sits_beside_the_target(void **state) {
  (void)state;
  char tmp[64];
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_temp_path("dir/a.exr", tmp, sizeof tmp, &err), SATF_OK);
  char expect[64];
  snprintf(expect, sizeof expect, "dir/a.exr.tmp-%ld", (long)getpid());
  assert_string_equal(tmp, expect);
  char tiny[8];
  assert_int_equal(satf_temp_path("dir/a.exr", tiny, sizeof tiny, &err),
                   SATF_ERR_ARGUMENT);
  assert_string_equal(err.message, "dir/a.exr: path is too long");
}

static void failed_commit_removes_the_temp_file(void **state) {
  (void)state;
  char dir[600], tmp[700], target[800];
  scratch(dir, sizeof dir, "commit");
  snprintf(tmp, sizeof tmp, "%s/x.tmp-1", dir);
  snprintf(target, sizeof target, "%s/absent/x", dir);
  put(tmp, "data", 4);
  satf_error err;
  satf_error_clear(&err);
  assert_int_equal(satf_commit_temp(tmp, target, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, "cannot rename"));
  int temps;
  assert_int_equal(entries(dir, &temps), 0);
  assert_int_equal(satf_file_size(tmp), -1);
}

/* Outputs never name an input or another output, however spelt. */
static void distinct_files_catch_every_spelling(void **state) {
  (void)state;
  char dir[512], in[600], alias[700], sym[600], hard[600], out[600];
  scratch(dir, sizeof dir, "distinct");
  snprintf(in, sizeof in, "%s/in.json", dir);
  put(in, "{}", 2);
  snprintf(alias, sizeof alias, "%s/./../distinct/in.json", dir);
  snprintf(sym, sizeof sym, "%s/link.json", dir);
  assert_int_equal(symlink("in.json", sym), 0);
  snprintf(hard, sizeof hard, "%s/hard.json", dir);
  assert_int_equal(link(in, hard), 0);
  snprintf(out, sizeof out, "%s/new.exr", dir);
  const char *same_as_in[] = {in, alias, sym, hard};
  satf_error err;
  for (int i = 0; i < 4; i++) {
    satf_file_role f[] = {{"the scene", in, 0}, {"-o", same_as_in[i], 1}};
    assert_int_equal(satf_check_distinct_files(f, 2, &err), SATF_ERR_ARGUMENT);
    assert_non_null(strstr(err.message, "is the same file as the scene"));
  }
  /* two outputs that do not exist yet, spelt differently */
  char out2[700];
  snprintf(out2, sizeof out2, "%s/../distinct/new.exr", dir);
  satf_file_role two[] = {
      {"the scene", in, 0}, {"-o", out, 1}, {"--png", out2, 1}};
  assert_int_equal(satf_check_distinct_files(two, 3, &err), SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "--png"));
  /* distinct files, absent options and two identical inputs are fine */
  satf_file_role ok[] = {{"the scene", in, 0},
                         {"--db", in, 0},
                         {"-o", out, 1},
                         {"--png", NULL, 1}};
  assert_int_equal(satf_check_distinct_files(ok, 4, &err), SATF_OK);
}

/* A temp file left by a killed run is removed by the next write to the same
 * path; one of a live process (a concurrent writer) is kept. */
static void stale_temp_files_are_cleaned_up(void **state) {
  (void)state;
  char dir[512], out[600], dead[700], live[700];
  scratch(dir, sizeof dir, "stale");
  snprintf(out, sizeof out, "%s/scene.json", dir);
  pid_t child = fork();
  assert_true(child >= 0);
  if (child == 0)
    _exit(0);
  assert_int_equal(waitpid(child, NULL, 0), child);
  snprintf(dead, sizeof dead, "%s.tmp-%ld", out, (long)child);
  snprintf(live, sizeof live, "%s.tmp-%ld", out, (long)getppid());
  put(dead, "old", 3);
  put(live, "busy", 4);
  satf_error err;
  assert_int_equal(satf_write_file_atomic(out, "{}", 2, &err), SATF_OK);
  struct stat sb;
  assert_int_not_equal(stat(dead, &sb), 0);
  assert_int_equal(stat(live, &sb), 0);
  assert_int_equal(stat(out, &sb), 0);
}

static void extensions_are_checked_without_case(void **state) {
  (void)state;
  assert_true(satf_path_has_extension("out/a.exr", ".exr"));
  assert_true(satf_path_has_extension("A.EXR", ".exr"));
  assert_false(satf_path_has_extension("a.png", ".exr"));
  assert_false(satf_path_has_extension(".exr", ".exr"));
  assert_false(satf_path_has_extension("dir/.exr", ".exr"));
  assert_false(satf_path_has_extension("a.exr.tmp", ".exr"));
  satf_error err;
  assert_int_equal(satf_check_output_extension("-o", NULL, ".exr", "x", &err),
                   SATF_OK);
  assert_int_equal(
      satf_check_output_extension("-o", "f.png", ".exr", "an EXR", &err),
      SATF_ERR_ARGUMENT);
  assert_string_equal(err.message,
                      "-o f.png: writes an EXR; give it a name ending in .exr");
}

/* An output named through a symbolic link is written through it: the link
 * stays a link, its target gets the bytes, and the temporary file sits
 * beside the target, so the rename stays on one file system. Relative
 * links, chains of links and a link to a file not yet there work alike; a
 * loop of links is refused. */
static void atomic_write_goes_through_symlinks(void **state) {
  (void)state;
  char dir[600], sub[700], target[800], link[800], chain[800], dangling[800],
      loop[800];
  scratch(dir, sizeof dir, "links");
  snprintf(sub, sizeof sub, "%s/sub", dir);
  assert_int_equal(mkdir(sub, 0755), 0);
  snprintf(target, sizeof target, "%s/target.exr", sub);
  snprintf(link, sizeof link, "%s/link.exr", dir);
  snprintf(chain, sizeof chain, "%s/chain.exr", dir);
  snprintf(dangling, sizeof dangling, "%s/dangling.exr", dir);
  snprintf(loop, sizeof loop, "%s/loop.exr", dir);
  put(target, "old", 3);
  assert_int_equal(symlink("sub/target.exr", link), 0);
  assert_int_equal(symlink("link.exr", chain), 0);
  assert_int_equal(symlink("sub/new.exr", dangling), 0);
  assert_int_equal(symlink("loop.exr", loop), 0);

  satf_error err;
  char tmp[1000];
  assert_int_equal(satf_temp_path(link, tmp, sizeof tmp, &err), SATF_OK);
  assert_non_null(strstr(tmp, "/sub/target.exr.tmp-"));
  assert_int_equal(satf_write_file_atomic(link, "new", 3, &err), SATF_OK);
  assert_int_equal(satf_write_file_atomic(chain, "newer", 5, &err), SATF_OK);
  struct stat st;
  assert_int_equal(lstat(link, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  assert_int_equal(lstat(chain, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  assert_int_equal(satf_file_size(target), 5);

  assert_int_equal(satf_write_file_atomic(dangling, "abc", 3, &err), SATF_OK);
  assert_int_equal(lstat(dangling, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  char made[800];
  snprintf(made, sizeof made, "%s/new.exr", sub);
  assert_int_equal(satf_file_size(made), 3);

  assert_int_equal(satf_write_file_atomic(loop, "x", 1, &err), SATF_ERR_IO);
  assert_non_null(strstr(err.message, "too many levels of symbolic links"));
  int temps;
  assert_int_equal(entries(sub, &temps), 2);
  assert_int_equal(temps, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(read_file_returns_content_up_to_the_exact_cap),
      cmocka_unit_test(read_file_of_an_empty_file),
      cmocka_unit_test(read_file_names_the_missing_file),
      cmocka_unit_test(read_file_refuses_a_directory),
      cmocka_unit_test(read_file_never_returns_a_truncated_file),
      cmocka_unit_test(atomic_write_replaces_content_and_leaves_no_temp),
      cmocka_unit_test(atomic_write_into_a_missing_directory_fails_cleanly),
      cmocka_unit_test(temp_path_sits_beside_the_target),
      cmocka_unit_test(failed_commit_removes_the_temp_file),
      cmocka_unit_test(distinct_files_catch_every_spelling),
      cmocka_unit_test(stale_temp_files_are_cleaned_up),
      cmocka_unit_test(extensions_are_checked_without_case),
      cmocka_unit_test(atomic_write_goes_through_symlinks),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
