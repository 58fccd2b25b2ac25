/* import_publish.c - a scene and the side files only it names (the density
 * grid, the strands) published as one unit (satf/import.h, "Publishing"):
 * side files under names derived from their bytes, the scene renamed into
 * place last, then the side files the replaced scene named removed. A run
 * killed at any point leaves the old scene with the side files it names,
 * or the new one with its own. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <fcntl.h>
#include <glob.h>
#include <limits.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "import_internal.h"
#include "satf/common.h"

/* base split as DIR/STEM EXT ("out/hair.vdb": "out/hair", ".vdb"): the
 * extension is the last dot of the file name, if any. */
static void split_base(const char *base, char *stem, size_t size,
                       const char **ext) {
  const char *slash = strrchr(base, '/');
  const char *dot = strrchr(slash ? slash + 1 : base, '.');
  if (!dot || dot == (slash ? slash + 1 : base))
    dot = base + strlen(base);
  snprintf(stem, size, "%.*s", (int)(dot - base), base);
  *ext = dot;
}

/* Removes BASE.tmp-PID files (and the writers' own BASE.tmp-PID.tmp-PID
 * inside them) of processes that no longer run: what a kill left. */
static void remove_stale_staging(const char *base) {
  char pattern[PATH_MAX + 16];
  int n = snprintf(pattern, sizeof pattern, "%s.tmp-*", base);
  if (n < 0 || (size_t)n >= sizeof pattern || strpbrk(base, "*?["))
    return;
  glob_t g;
  if (glob(pattern, GLOB_NOSORT, NULL, &g) != 0)
    return;
  size_t skip = strlen(base) + 5;
  for (size_t i = 0; i < g.gl_pathc; i++) {
    const char *p = g.gl_pathv[i] + skip;
    int all_dead = 1, ok = 1;
    while (ok && *p) {
      char *end;
      long pid = strtol(p, &end, 10);
      ok = end != p && pid > 0;
      if (ok &&
          (pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno != ESRCH))
        all_dead = 0;
      p = end;
      if (ok && *p)
        ok = strncmp(p, ".tmp-", 5) == 0 ? (p += 5, 1) : 0;
    }
    if (ok && all_dead)
      remove(g.gl_pathv[i]);
  }
  globfree(&g);
}

/* FNV-1a (32 bits) of the file's bytes; 0 on a read error. */
static int hash_file(const char *path, uint32_t *hash, satf_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot read back: %s", path,
                          strerror(errno)) == SATF_OK;
  uint32_t h = 2166136261u;
  unsigned char buf[1 << 16];
  size_t got;
  while ((got = fread(buf, 1, sizeof buf, f)) > 0)
    for (size_t i = 0; i < got; i++)
      h = (h ^ buf[i]) * 16777619u;
  int bad = ferror(f);
  fclose(f);
  if (bad) {
    satf_error_set(err, SATF_ERR_IO, "%s: cannot read back", path);
    return 0;
  }
  *hash = h;
  return 1;
}

/* Whether two files hold the same bytes. */
static int same_bytes(const char *a, const char *b) {
  FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
  int same = fa && fb;
  while (same) {
    int ca = getc(fa), cb = getc(fb);
    same = ca == cb;
    if (ca == EOF)
      break;
  }
  if (fa)
    fclose(fa);
  if (fb)
    fclose(fb);
  return same;
}

/* Whether path is a published side file: its name is STEM-XXXXXXXX.EXT
 * and XXXXXXXX is the hash of its bytes. Only satf_import_publish_scene
 * makes such files, so only those are ever removed. */
static int is_published(const char *path) {
  const char *name = strrchr(path, '/');
  name = name ? name + 1 : path;
  const char *dot = strrchr(name, '.');
  if (!dot || dot - name < 10 || dot[-9] != '-')
    return 0;
  unsigned named = 0;
  for (const char *c = dot - 8; c < dot; c++) {
    int v = *c >= '0' && *c <= '9'   ? *c - '0'
            : *c >= 'a' && *c <= 'f' ? *c - 'a' + 10
                                     : -1;
    if (v < 0)
      return 0;
    named = named * 16 + (unsigned)v;
  }
  satf_error ignored;
  uint32_t h;
  return hash_file(path, &h, &ignored) && h == named;
}

/* fsync of path's directory, so the renames before it reach the disk before
 * the scene's rename (a power cut keeps the order a kill keeps). */
static void sync_dir_of(const char *path) {
  char dir[PATH_MAX];
  const char *slash = strrchr(path, '/');
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) : 1,
           slash ? (slash == path ? "/" : path) : ".");
  int fd = open(dir, O_RDONLY);
  if (fd >= 0) {
    fsync(fd);
    close(fd);
  }
}

satf_status satf_import_stage_side(satf_import_side *side, satf_error *err) {
  side->published[0] = side->staging[0] = '\0';
  side->created = 0;
  if (!side->base || !side->base[0] || !side->write)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_import_stage_side: no name or no writer");
  char stem[PATH_MAX];
  const char *ext;
  remove_stale_staging(side->base);
  split_base(side->base, stem, sizeof stem, &ext);
  int n = snprintf(side->staging, sizeof side->staging, "%s.tmp-%ld",
                   side->base, (long)getpid());
  if (n < 0 || (size_t)n >= sizeof side->staging ||
      strlen(stem) + 9 + strlen(ext) >= sizeof side->published) {
    side->staging[0] = '\0';
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: path is too long",
                          side->base);
  }
  satf_status st = side->write(side->staging, side->ctx, err);
  uint32_t h = 0;
  if (st == SATF_OK && !hash_file(side->staging, &h, err))
    st = SATF_ERR_IO;
  if (st != SATF_OK) {
    remove(side->staging);
    side->staging[0] = '\0';
    return st;
  }
  snprintf(side->published, sizeof side->published, "%s-%08x%s", stem,
           (unsigned)h, ext);
  return SATF_OK;
}

void satf_import_discard_sides(satf_import_side *sides, int n_sides) {
  for (int i = 0; i < n_sides; i++) {
    if (sides[i].staging[0])
      remove(sides[i].staging);
    if (sides[i].created)
      remove(sides[i].published);
    sides[i].staging[0] = '\0';
    sides[i].created = 0;
  }
}

/* Renames each staged side file to its published name (or drops it when
 * that name already holds the same bytes: a repeated import). */
static satf_status publish_sides(satf_import_side *sides, int n_sides,
                                 satf_error *err) {
  for (int i = 0; i < n_sides; i++) {
    satf_import_side *side = &sides[i];
    if (!side->staging[0])
      continue;
    struct stat sb;
    if (stat(side->published, &sb) == 0) {
      int same = same_bytes(side->staging, side->published);
      remove(side->staging);
      side->staging[0] = '\0';
      if (!same)
        return satf_error_set(err, SATF_ERR_IO,
                              "%s: already exists with other contents (a "
                              "hash collision): remove it and import again",
                              side->published);
      continue;
    }
    if (rename(side->staging, side->published) != 0)
      return satf_error_set(err, SATF_ERR_IO,
                            "%s: cannot rename %s into place: %s",
                            side->published, side->staging, strerror(errno));
    side->staging[0] = '\0';
    side->created = 1;
  }
  for (int i = 0; i < n_sides; i++)
    if (sides[i].published[0])
      sync_dir_of(sides[i].published);
  return SATF_OK;
}

/* The side-file paths a scene names (its strands and its density grids),
 * as resolved when loaded: up to max, into paths (not copied). */
static int named_paths(const satf_scene *scene, const char **paths, int max) {
  int n = 0;
  if (scene->strands_file && n < max)
    paths[n++] = scene->strands_file;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_density *d = &scene->macro_clusters[m].prototype.density;
    if (d->type == SATF_SCENE_DENSITY_VDB && d->vdb_file && n < max)
      paths[n++] = d->vdb_file;
  }
  return n;
}

/* Whether a and b are one file (both existing) or the same path. */
static int same_file(const char *a, const char *b) {
  struct stat sa, sb;
  if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  return strcmp(a, b) == 0;
}

#define MAX_NAMED 65536

satf_status satf_import_publish_scene(const satf_scene *scene, const char *path,
                                      satf_import_side *sides, int n_sides,
                                      satf_error *err) {
  /* What the scene being replaced names, read before it goes. A file that
   * is not a scene (or not ours) names nothing. */
  satf_scene *old = NULL;
  satf_error ignored;
  struct stat sb;
  if (stat(path, &sb) == 0 && S_ISREG(sb.st_mode) &&
      satf_scene_load(path, &old, &ignored) != SATF_OK)
    old = NULL;
  /* The side files go into place together, just before the scene: a kill
   * before this leaves only staging files, which the next run removes. */
  satf_status st = publish_sides(sides, n_sides, err);
  if (st == SATF_OK)
    st = satf_scene_write(scene, path, err);
  const char **was = calloc(MAX_NAMED, sizeof *was);
  const char **now = calloc(MAX_NAMED, sizeof *now);
  int n_was = old && was ? named_paths(old, was, MAX_NAMED) : 0;
  int n_now = now ? named_paths(scene, now, MAX_NAMED) : 0;
  if (st != SATF_OK) {
    /* The old scene stays, naming its own files: the new ones it does not
     * name go (a file shared with it, same bytes, stays). */
    for (int i = 0; i < n_sides; i++) {
      if (sides[i].staging[0])
        remove(sides[i].staging);
      sides[i].staging[0] = '\0';
      int kept = !sides[i].created;
      for (int k = 0; k < n_was && !kept; k++)
        kept = same_file(was[k], sides[i].published);
      if (!kept)
        remove(sides[i].published);
    }
  } else {
    /* The old scene's side files that an import published (named by the
     * hash of their bytes) and the new scene does not name. */
    for (int k = 0; k < n_was; k++) {
      int named = 0;
      for (int j = 0; j < n_now && !named; j++)
        named = same_file(was[k], now[j]);
      for (int j = 0; j < k && !named; j++) /* named twice: removed once */
        named = strcmp(was[j], was[k]) == 0;
      if (!named && is_published(was[k]))
        remove(was[k]);
    }
  }
  free(was);
  free(now);
  satf_scene_destroy(old);
  return st;
}
