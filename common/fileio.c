/* fileio.c - see fileio.h. */
#define _POSIX_C_SOURCE 200809L
#include "common/fileio.h"

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

long long satf_file_size(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0)
    return -1;
  return (long long)st.st_size;
}
