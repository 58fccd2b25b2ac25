/* test_publish.c - a scene and its side files published as one unit
 * (satf_import_stage_side, satf_import_publish_scene):
 * side files staged, then renamed to names of their bytes' hash together
 * just before the scene, which is renamed last, the
 * replaced scene's side files removed only once the new scene is in place,
 * and the leftovers of killed runs (*.tmp-PID of dead processes) cleaned
 * by the next run. A scene write that fails (what a kill between the side
 * files and the scene amounts to) leaves the old scene naming a side file
 * whose bytes are unchanged. */
#define _XOPEN_SOURCE 700
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "import_internal.h"
#include "satf/common.h"
#include "test_util.h"

typedef struct bytes_job {
  const char *text;     /* what the side file holds */
  const char *sabotage; /* when set: a directory made there after writing */
} bytes_job;

static satf_status write_bytes(const char *path, void *ctx, satf_error *err) {
  const bytes_job *j = ctx;
  satf_status st = satf_write_file_atomic(path, j->text, strlen(j->text), err);
  if (j->sabotage)
    mkdir(j->sabotage, 0755);
  return st;
}

static int exists(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0;
}

/* A process id that has exited (its temporary files are stale). */
static long dead_pid(void) {
  pid_t pid = fork();
  if (pid == 0)
    _exit(0);
  assert_true(pid > 0);
  waitpid(pid, NULL, 0);
  return (long)pid;
}

static void touch(const char *path) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs("left by a kill", f);
  fclose(f);
}

/* A one-cluster scene at path whose density is the VDB vdb and whose
 * strands are strands (either may be NULL). */
static satf_scene *scene_naming(const char *path, const char *vdb,
                                const char *strands) {
  static const char json[] =
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, 0], "
      "[0, 1, 0]], \"a\": 0.5, \"density\": {\"type\": \"vdb\", \"file\": "
      "\"placeholder.vdb\"}}}]}";
  satf_scene *scene;
  satf_error err;
  if (satf_scene_parse(json, strlen(json), path, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_scene_density *d = &scene->macro_clusters[0].prototype.density;
  free(d->vdb_file);
  d->vdb_file = malloc(strlen(vdb) + 1);
  strcpy(d->vdb_file, vdb);
  if (strands) {
    scene->strands_file = malloc(strlen(strands) + 1);
    strcpy(scene->strands_file, strands);
  }
  return scene;
}

/* What the scene file at path names as its VDB (resolved). */
static char *named_vdb(const char *path) {
  satf_scene *scene;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  const char *f = scene->macro_clusters[0].prototype.density.vdb_file;
  char *copy = malloc(strlen(f) + 1);
  strcpy(copy, f);
  satf_scene_destroy(scene);
  return copy;
}

static void assert_file_holds(const char *path, const char *text) {
  size_t size;
  unsigned char *got = test_read_file(path, &size);
  assert_int_equal(size, strlen(text));
  assert_memory_equal(got, text, size);
  free(got);
}

static void publish_as_one_unit(void **state) {
  (void)state;
  char dir[1024], scene_path[1100], base[1100], hair_base[1100], tmp[1200];
  test_path(dir, sizeof dir, "publish");
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  assert_int_equal(system(cmd), 0);
  assert_int_equal(mkdir(dir, 0755), 0);
  snprintf(scene_path, sizeof scene_path, "%s/s.json", dir);
  snprintf(base, sizeof base, "%s/hair.vdb", dir);
  snprintf(hair_base, sizeof hair_base, "%s/s.strands.hair", dir);
  satf_error err;

  /* The first import: a VDB and strands, then the scene naming them. */
  bytes_job old_vdb = {"OLD grid bytes", NULL}, old_hair = {"OLD hair", NULL};
  satf_import_side sides[2] = {{base, write_bytes, &old_vdb, "", "", 0},
                               {hair_base, write_bytes, &old_hair, "", "", 0}};
  assert_int_equal(satf_import_stage_side(&sides[0], &err), SATF_OK);
  assert_int_equal(satf_import_stage_side(&sides[1], &err), SATF_OK);
  /* base-XXXXXXXX.ext, beside the base */
  assert_int_equal(strlen(sides[0].published), strlen(base) + 9);
  assert_int_equal(strncmp(sides[0].published, base, strlen(base) - 4), 0);
  assert_int_equal(strncmp(sides[1].published + strlen(dir), "/s.strands-", 11),
                   0);
  assert_string_equal(sides[1].published + strlen(dir) + 19, ".hair");
  char old_vdb_path[1200], old_hair_path[1200];
  strcpy(old_vdb_path, sides[0].published);
  strcpy(old_hair_path, sides[1].published);
  satf_scene *scene = scene_naming(scene_path, old_vdb_path, old_hair_path);
  assert_int_equal(satf_import_publish_scene(scene, scene_path, sides, 2, &err),
                   SATF_OK);
  satf_scene_destroy(scene);
  char *named = named_vdb(scene_path);
  assert_string_equal(named, old_vdb_path);
  free(named);

  /* The second import fails between its side files and the scene (the
   * scene's temporary file cannot be made): the old scene stays, naming
   * the old VDB, whose bytes are unchanged; the new VDB is gone. */
  snprintf(tmp, sizeof tmp, "%s.tmp-%ld", scene_path, (long)getpid());
  bytes_job new_vdb = {"NEW grid bytes", tmp};
  satf_import_side next = {base, write_bytes, &new_vdb, "", "", 0};
  assert_int_equal(satf_import_stage_side(&next, &err), SATF_OK);
  assert_string_not_equal(next.published, old_vdb_path);
  assert_false(exists(next.published)); /* staged, not yet published */
  char staged[4200];
  strcpy(staged, next.staging);
  assert_true(exists(staged));
  scene = scene_naming(scene_path, next.published, old_hair_path);
  assert_int_not_equal(
      satf_import_publish_scene(scene, scene_path, &next, 1, &err), SATF_OK);
  satf_scene_destroy(scene);
  named = named_vdb(scene_path);
  assert_string_equal(named, old_vdb_path);
  free(named);
  assert_file_holds(old_vdb_path, "OLD grid bytes");
  assert_file_holds(old_hair_path, "OLD hair");
  assert_false(exists(next.published));
  assert_false(exists(staged));
  assert_int_equal(rmdir(tmp), 0);

  /* A killed run's leftovers: staging files of the side files (with the
   * writer's own temporary inside) and of the scene, from a dead process;
   * one of a live process (ours) stays. */
  long dead = dead_pid();
  char stale[4][1300];
  snprintf(stale[0], sizeof stale[0], "%s.tmp-%ld", base, dead);
  snprintf(stale[1], sizeof stale[1], "%s.tmp-%ld.tmp-%ld", base, dead, dead);
  snprintf(stale[2], sizeof stale[2], "%s.tmp-%ld", scene_path, dead);
  snprintf(stale[3], sizeof stale[3], "%s.tmp-%ld", hair_base, dead);
  for (int i = 0; i < 4; i++)
    touch(stale[i]);
  char live[1300];
  snprintf(live, sizeof live, "%s.tmp-1", base); /* init never exits */
  touch(live);

  /* The third import succeeds: the new scene names the new VDB and the
   * old strands (same bytes: the same name); the old VDB is removed. */
  new_vdb.sabotage = NULL;
  bytes_job same_hair = {"OLD hair", NULL};
  satf_import_side third[2] = {{base, write_bytes, &new_vdb, "", "", 0},
                               {hair_base, write_bytes, &same_hair, "", "", 0}};
  assert_int_equal(satf_import_stage_side(&third[0], &err), SATF_OK);
  assert_int_equal(satf_import_stage_side(&third[1], &err), SATF_OK);
  assert_string_equal(third[1].published, old_hair_path);
  assert_int_equal(third[1].created, 0);
  scene = scene_naming(scene_path, third[0].published, third[1].published);
  if (satf_import_publish_scene(scene, scene_path, third, 2, &err) != SATF_OK)
    fail_msg("%s", err.message);
  satf_scene_destroy(scene);
  named = named_vdb(scene_path);
  assert_string_equal(named, third[0].published);
  free(named);
  assert_file_holds(third[0].published, "NEW grid bytes");
  assert_false(exists(old_vdb_path));
  assert_file_holds(old_hair_path, "OLD hair");
  for (int i = 0; i < 4; i++)
    if (exists(stale[i]))
      fail_msg("%s: a dead run's temporary file was not removed", stale[i]);
  assert_true(exists(live));
  remove(live);

  /* A scene naming a file that is not a published one (a name that looks
   * like one, but not the hash of its bytes) never loses it. */
  char mine[1200];
  snprintf(mine, sizeof mine, "%s/mine-00000000.vdb", dir);
  touch(mine);
  scene = scene_naming(scene_path, mine, NULL);
  assert_int_equal(satf_import_publish_scene(scene, scene_path, NULL, 0, &err),
                   SATF_OK);
  satf_scene_destroy(scene);
  assert_false(exists(third[0].published)); /* published: removed */
  assert_false(exists(old_hair_path));
  scene = scene_naming(scene_path, third[0].published, NULL);
  assert_int_equal(satf_import_publish_scene(scene, scene_path, NULL, 0, &err),
                   SATF_OK);
  satf_scene_destroy(scene);
  assert_true(exists(mine));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(publish_as_one_unit),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
