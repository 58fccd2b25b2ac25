/* data_dir.c - where an installed tool finds its data: beside its bin/
 * folder in share/satf, so an installation works from any prefix and can
 * be moved whole. */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "satf/common.h"

/* This program's folder (its bin/), symbolic links resolved. */
static int exe_dir(char *out, size_t size) {
  char exe[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0)
    return -1;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash)
    return -1;
  *slash = '\0';
  int len = snprintf(out, size, "%s", exe);
  return len > 0 && (size_t)len < size ? 0 : -1;
}

/* dir's parent (dir is absolute), in place; -1 at the root. */
static int up(char *dir) {
  char *slash = strrchr(dir, '/');
  if (!slash || slash == dir)
    return -1;
  *slash = '\0';
  return 0;
}

int satf_data_dir(char *out, size_t size) {
  const char *env = getenv("SATF_DATA_DIR");
  if (env && *env) {
    int len = snprintf(out, size, "%s", env);
    return len > 0 && (size_t)len < size ? 0 : -1;
  }
  char dir[PATH_MAX];
  if (exe_dir(dir, sizeof dir) != 0 || up(dir) != 0)
    return -1;
  int len = snprintf(out, size, "%s/share/satf", dir);
  return len > 0 && (size_t)len < size ? 0 : -1;
}

static int regular(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

const char *satf_default_database(int fiber, char *out, size_t size) {
  const char *name =
      fiber ? "satf-fiber.hrirdb.exr" : "satf-default.hrirdb.exr";
  char dir[PATH_MAX];
  int len;
  if (satf_data_dir(dir, sizeof dir) == 0 &&
      (len = snprintf(out, size, "%s/%s", dir, name)) > 0 &&
      (size_t)len < size && regular(out))
    return out;
  return NULL;
}
