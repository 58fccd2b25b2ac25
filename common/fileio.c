/* fileio.c - see fileio.h. */
#define _POSIX_C_SOURCE 200809L
#include "satf/common.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

satf_status satf_temp_path(const char *path, char *tmp, size_t size,
                           satf_error *err) {
  int n = snprintf(tmp, size, "%s.tmp-%ld", path, (long)getpid());
  if (n < 0 || (size_t)n >= size)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path is too long", path);
  return SATF_OK;
}

satf_status satf_commit_temp(const char *tmp, const char *path,
                             satf_error *err) {
  int fd = open(tmp, O_RDONLY);
  if (fd >= 0) {
    fsync(fd);
    close(fd);
  }
  if (rename(tmp, path) != 0) {
    int e = errno;
    remove(tmp);
    return satf_error_set(err, SATF_ERR_IO,
                          "%s: cannot rename %s into place: %s", path, tmp,
                          strerror(e));
  }
  return SATF_OK;
}

satf_status satf_write_file_atomic(const char *path, const void *data,
                                   size_t size, satf_error *err) {
  char tmp[4096];
  satf_status st = satf_temp_path(path, tmp, sizeof tmp, err);
  if (st != SATF_OK)
    return st;
  FILE *f = fopen(tmp, "wb");
  if (!f)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot create %s: %s", path,
                          tmp, strerror(errno));
  size_t put = fwrite(data, 1, size, f);
  if (fclose(f) != 0 || put != size) {
    remove(tmp);
    return satf_error_set(err, SATF_ERR_IO, "%s: write failed", path);
  }
  return satf_commit_temp(tmp, path, err);
}

long long satf_file_size(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0)
    return -1;
  return (long long)st.st_size;
}
