/* fileio.c - crash-safe output and capped input, declared in
 * satf/common.h. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "satf/common.h"

#include <errno.h>
#include <fcntl.h>
#include <glob.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Removes PATH.tmp-PID files whose process is gone: what a run killed
 * between writing and renaming left behind. Files of live processes (a
 * concurrent writer) are kept. */
static void remove_stale_temps(const char *path) {
  char pattern[4200];
  int n = snprintf(pattern, sizeof pattern, "%s.tmp-*", path);
  if (n < 0 || (size_t)n >= sizeof pattern || strpbrk(path, "*?["))
    return;
  glob_t g;
  if (glob(pattern, GLOB_NOSORT, NULL, &g) != 0)
    return;
  size_t base = strlen(path) + 5;
  for (size_t i = 0; i < g.gl_pathc; i++) {
    const char *digits = g.gl_pathv[i] + base;
    char *end = NULL;
    long pid = strtol(digits, &end, 10);
    if (end == digits || *end || pid <= 0 || pid == (long)getpid())
      continue;
    if (kill((pid_t)pid, 0) != 0 && errno == ESRCH)
      remove(g.gl_pathv[i]);
  }
  globfree(&g);
}

/* The file an output path names: path itself, or where its chain of
 * symbolic links ends (the last target need not exist yet). Renaming over a
 * link would replace the link by a regular file and leave its target
 * stale; writing through it, as cp and the compositors do, keeps both. The
 * temporary file goes next to the target so that the rename stays within
 * one file system. Fails for a chain longer than 40 links (a loop). */
static satf_status output_target(const char *path, char *out, size_t size,
                                 satf_error *err) {
  if (strlen(path) >= size)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path is too long", path);
  strcpy(out, path);
  for (int links = 0; links < 40; links++) {
    struct stat st;
    if (lstat(out, &st) != 0 || !S_ISLNK(st.st_mode))
      return SATF_OK;
    char to[4096];
    ssize_t n = readlink(out, to, sizeof to - 1);
    if (n < 0 || (size_t)n >= sizeof to - 1)
      return satf_error_set(err, SATF_ERR_IO,
                            "%s: cannot read the symbolic link %s", path, out);
    to[n] = 0;
    const char *slash = strrchr(out, '/');
    size_t dir = to[0] == '/' || !slash ? 0 : (size_t)(slash - out) + 1;
    if (dir + (size_t)n >= size)
      return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path is too long",
                            path);
    memmove(out + dir, to, (size_t)n + 1);
  }
  return satf_error_set(err, SATF_ERR_IO,
                        "%s: too many levels of symbolic links", path);
}

satf_status satf_temp_path(const char *path, char *tmp, size_t size,
                           satf_error *err) {
  size_t len = strlen(path);
  if (len == 0 || path[len - 1] == '/')
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "'%s': an output needs a file name", path);
  char target[4096];
  satf_status st = output_target(path, target, sizeof target, err);
  if (st != SATF_OK)
    return st;
  remove_stale_temps(target);
  int n = snprintf(tmp, size, "%s.tmp-%ld", target, (long)getpid());
  if (n < 0 || (size_t)n >= size)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path is too long", path);
  return SATF_OK;
}

satf_status satf_commit_temp(const char *tmp, const char *path,
                             satf_error *err) {
  /* Delayed allocation (ext4, XFS, NFS) can report a full disk or an I/O
   * error only here: a file that did not reach the disk is never renamed
   * into place. */
  int fd = open(tmp, O_RDONLY);
  if (fd < 0 || fsync(fd) != 0) {
    int e = errno;
    if (fd >= 0)
      close(fd);
    remove(tmp);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot write: %s", path,
                          strerror(e));
  }
  close(fd);
  char target[4096];
  satf_status st = output_target(path, target, sizeof target, err);
  if (st != SATF_OK) {
    remove(tmp);
    return st;
  }
  if (rename(tmp, target) != 0) {
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
  int e = put != size ? errno : 0;
  if (fclose(f) != 0 && !e)
    e = errno;
  if (e || put != size) {
    remove(tmp);
    return satf_error_set(err, SATF_ERR_IO, "%s: write failed: %s", path,
                          strerror(e ? e : EIO));
  }
  return satf_commit_temp(tmp, path, err);
}

long long satf_file_size(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0)
    return -1;
  return (long long)st.st_size;
}

/* Reads exactly n bytes into buf and then checks that the file ends there,
 * so a file that changed after fstat cannot come back truncated. */
static satf_status read_exactly(FILE *f, const char *path, unsigned char *buf,
                                size_t n, satf_error *err) {
  size_t got = fread(buf, 1, n, f);
  if (ferror(f))
    return satf_error_set(err, SATF_ERR_IO, "%s: read failed: %s", path,
                          strerror(errno));
  if (got != n || fgetc(f) != EOF)
    return satf_error_set(err, SATF_ERR_IO, "%s: changed size while being read",
                          path);
  return SATF_OK;
}

satf_status satf_read_file(const char *path, size_t max_bytes, void **data,
                           size_t *size, satf_error *err) {
  *data = NULL;
  *size = 0;
  /* O_NONBLOCK: opening a FIFO for reading would wait for a writer
   * forever; it is refused below with every other non-regular file. */
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
  if (!f) {
    int e = errno;
    if (fd >= 0)
      close(fd);
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          strerror(e));
  }
  /* fstat the open file, not the path, so the checks hold for what is read */
  struct stat st;
  satf_status s = SATF_OK;
  if (fstat(fileno(f), &st) != 0)
    s = satf_error_set(err, SATF_ERR_IO, "%s: read failed: %s", path,
                       strerror(errno));
  else if (!S_ISREG(st.st_mode))
    s = satf_error_set(err, SATF_ERR_IO, "%s: not a regular file", path);
  else if ((unsigned long long)st.st_size > max_bytes ||
           (unsigned long long)st.st_size >= SIZE_MAX)
    s = satf_error_set(err, SATF_ERR_IO,
                       "%s: %lld bytes is over the limit of %zu bytes", path,
                       (long long)st.st_size, max_bytes);
  unsigned char *buf = NULL;
  size_t n = s == SATF_OK ? (size_t)st.st_size : 0;
  if (s == SATF_OK && !(buf = malloc(n + 1)))
    s = satf_error_set(err, SATF_ERR_NOMEM, "%s: cannot hold %lld bytes", path,
                       (long long)st.st_size);
  if (s == SATF_OK)
    s = read_exactly(f, path, buf, n, err);
  fclose(f);
  if (s != SATF_OK) {
    free(buf);
    return s;
  }
  buf[n] = '\0';
  *data = buf;
  *size = n;
  return SATF_OK;
}

/* A file's identity: device and inode when it exists; otherwise the
 * canonical directory plus its name (dev = ino = 0). */
typedef struct file_key {
  dev_t dev;
  ino_t ino;
  char name[PATH_MAX + NAME_MAX + 2];
} file_key;

static void file_key_of(const char *path, file_key *k) {
  struct stat sb;
  memset(k, 0, sizeof *k);
  if (stat(path, &sb) == 0) {
    k->dev = sb.st_dev;
    k->ino = sb.st_ino;
    return;
  }
  char dir[PATH_MAX], resolved[PATH_MAX];
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  size_t dlen = slash ? (size_t)(slash - path) : 0;
  if (dlen >= sizeof dir)
    dlen = sizeof dir - 1;
  memcpy(dir, path, dlen);
  dir[dlen] = '\0';
  if (!slash)
    snprintf(dir, sizeof dir, ".");
  else if (dlen == 0)
    snprintf(dir, sizeof dir, "/");
  if (realpath(dir, resolved))
    snprintf(k->name, sizeof k->name, "%s/%s", resolved, base);
  else
    snprintf(k->name, sizeof k->name, "%s", path);
}

static int same_key(const file_key *a, const file_key *b) {
  if (a->ino || b->ino)
    return a->ino == b->ino && a->dev == b->dev;
  return strcmp(a->name, b->name) == 0;
}

satf_status satf_check_distinct_files(const satf_file_role *files, int n,
                                      satf_error *err) {
  for (int i = 0; i < n; i++) {
    if (!files[i].path || !files[i].is_output)
      continue;
    file_key ki;
    file_key_of(files[i].path, &ki);
    for (int j = 0; j < n; j++) {
      if (j == i || !files[j].path || (files[j].is_output && j < i))
        continue;
      file_key kj;
      file_key_of(files[j].path, &kj);
      if (same_key(&ki, &kj))
        return satf_error_set(err, SATF_ERR_ARGUMENT,
                              "%s %s is the same file as %s %s: refusing to "
                              "overwrite it",
                              files[i].what, files[i].path, files[j].what,
                              files[j].path);
    }
  }
  return SATF_OK;
}

int satf_path_has_extension(const char *path, const char *ext) {
  size_t n = strlen(path), e = strlen(ext);
  if (n <= e || path[n - e - 1] == '/')
    return 0;
  for (size_t i = 0; i < e; i++) {
    char a = path[n - e + i], b = ext[i];
    if (a >= 'A' && a <= 'Z')
      a = (char)(a - 'A' + 'a');
    if (a != b)
      return 0;
  }
  return 1;
}

satf_status satf_check_output_extension(const char *what, const char *path,
                                        const char *ext, const char *kind,
                                        satf_error *err) {
  if (!path || satf_path_has_extension(path, ext))
    return SATF_OK;
  if (!path[0])
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s '': an output needs a file name", what);
  return satf_error_set(err, SATF_ERR_ARGUMENT,
                        "%s %s: writes %s; give it a name ending in %s", what,
                        path, kind, ext);
}
