/* test_write.c - satf_scene_write and satf_scene_to_json, the one writer of
 * the scene format: every sample scene reads back as the same scene (every
 * field and every key), writing that gives the same bytes, and a scene
 * built in memory (as the importer builds one) reads back as built. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <dirent.h>
#include <limits.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/scene.h"
#include "test_util.h"

/* Snapshots of two scenes agree at frame f (a renderer's view of keys). */
static void assert_same_at(const satf_scene *a, const satf_scene *b, double f) {
  satf_scene *sa, *sb;
  satf_error err;
  assert_int_equal(satf_scene_at_frame(a, f, &sa, &err), SATF_OK);
  assert_int_equal(satf_scene_at_frame(b, f, &sb, &err), SATF_OK);
  if (!satf_scene_equal(sa, sb))
    fail_msg("%s: snapshots differ at frame %g", a->name, f);
  satf_scene_destroy(sa);
  satf_scene_destroy(sb);
}

/* Whether two paths name the same place: their directories resolve to the
 * same directory (realpath) and their names agree; paths whose directory
 * does not exist must be equal strings. */
static int same_place(const char *a, const char *b) {
  if (!a || !b)
    return a == b;
  char da[PATH_MAX], db[PATH_MAX], ra[PATH_MAX], rb[PATH_MAX];
  const char *sa = strrchr(a, '/'), *sb = strrchr(b, '/');
  snprintf(da, sizeof da, "%.*s", sa ? (int)(sa - a) : 1, sa ? a : ".");
  snprintf(db, sizeof db, "%.*s", sb ? (int)(sb - b) : 1, sb ? b : ".");
  if (!realpath(da, ra) || !realpath(db, rb))
    return strcmp(a, b) == 0;
  return strcmp(ra, rb) == 0 && strcmp(sa ? sa + 1 : a, sb ? sb + 1 : b) == 0;
}

/* *dst = a copy of src when both name the same place. */
static void align(char **dst, const char *src) {
  if (!src || !*dst || !same_place(src, *dst))
    return;
  free(*dst);
  *dst = malloc(strlen(src) + 1);
  assert_non_null(*dst);
  strcpy(*dst, src);
}

/* b's paths replaced by a's where they name the same place (a file
 * written elsewhere names the same files by other strings). */
static void align_paths(const satf_scene *a, satf_scene *b) {
  align(&b->database, a->database);
  align(&b->strands_file, a->strands_file);
  for (int m = 0; m < a->n_meshes && m < b->n_meshes; m++)
    align(&b->meshes[m].file, a->meshes[m].file);
  for (int m = 0; m < a->n_macro_clusters && m < b->n_macro_clusters; m++)
    align(&b->macro_clusters[m].prototype.density.vdb_file,
          a->macro_clusters[m].prototype.density.vdb_file);
}

/* parse -> write -> parse is the same scene; write(parse(write(x))) is
 * write(x), byte for byte. */
static void round_trip(const char *path) {
  satf_scene *scene, *again;
  satf_error err;
  if (satf_scene_load(path, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_scene_warning_count(scene), 0);
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", SATF_SAMPLES_DIR);
  char *text, *text2;
  assert_int_equal(satf_scene_to_json(scene, dir, &text, &err), SATF_OK);
  if (satf_scene_parse(text, strlen(text), path, &again, &err) != SATF_OK)
    fail_msg("%s written:\n%s\n%s", path, text, err.message);
  assert_int_equal(satf_scene_warning_count(again), 0);
  if (!satf_scene_equal(scene, again))
    fail_msg("%s: the written scene reads back different:\n%s", path, text);
  assert_int_equal(satf_scene_to_json(again, dir, &text2, &err), SATF_OK);
  assert_string_equal(text, text2);
  int first, last;
  if (satf_scene_frame_range(scene, &first, &last))
    for (double f = first - 1; f <= last + 1; f += 0.25)
      assert_same_at(scene, again, f);
  free(text);
  free(text2);
  satf_scene_destroy(again);

  /* Through a file elsewhere: paths still name the same files. */
  char out[1024];
  test_path(out, sizeof out, "written.json");
  assert_int_equal(satf_scene_write(scene, out, &err), SATF_OK);
  if (satf_scene_load(out, &again, &err) != SATF_OK)
    fail_msg("%s", err.message);
  align_paths(scene, again);
  if (!satf_scene_equal(scene, again))
    fail_msg("%s: written to %s, it reads back different", path, out);
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
}

static void test_samples_round_trip(void **state) {
  (void)state;
  DIR *d = opendir(SATF_SAMPLES_DIR);
  assert_non_null(d);
  int n = 0;
  for (struct dirent *e; (e = readdir(d));) {
    size_t len = strlen(e->d_name);
    if (len < 6 || strcmp(e->d_name + len - 5, ".json") != 0)
      continue;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", SATF_SAMPLES_DIR, e->d_name);
    round_trip(path);
    n++;
  }
  closedir(d);
  assert_true(n >= 5);
}

/* Every kind of key and every optional key, in one scene. */
static const char KEYED[] =
    "{\"description\": \"all of it\", \"animation\": {\"fps\": 12.5, "
    "\"frames\": [-2, 30]},"
    " \"database\": \"sub/db.exr\", \"strands\": \"hair.strands.hair\","
    " \"meshes\": [{\"file\": \"/abs/head.obj\", \"color\": [0.2, 0.3, 0.4],"
    "   \"transform\": {\"translate\": [1, 2, 3], \"scale\": 2}}],"
    " \"camera\": {\"target\": [0, 0.5, 0], \"up\": [0.1, 1, 0.2],"
    "   \"fov_y\": 33.3, \"near\": 0.5, \"far\": 90,"
    "   \"keys\": [{\"frame\": 0, \"up\": [0.3, 1, 0]},"
    "            {\"frame\": 10.5, \"position\": [1, 2, 9], \"fov_y\": 20}]},"
    " \"lights\": [{\"direction\": [0.3, -0.7, -0.61], \"keys\": ["
    "   {\"frame\": 1, \"color\": [1, 0.5, 0.25]},"
    "   {\"frame\": 4, \"direction\": [-0.37, -0.2, -0.9]}]},"
    "   {\"type\": \"point\", \"position\": [4, 5, 6], \"intensity\": 30,"
    "    \"keys\": [{\"frame\": 2, \"position\": [4, 6, 6]},"
    "             {\"frame\": 3, \"intensity\": 7}]}],"
    " \"effects\": {\"self_shadow\": false},"
    " \"material\": {\"shift_I\": 0.05, \"f_dif\": [0.3, 0.2, 0.1],"
    "   \"model\": \"physical\", \"melanin\": 0.25, \"redness\": 0.5,"
    "   \"roughness\": 0.2, \"radial_roughness\": 0.7,"
    "   \"cuticle_tilt\": -3, \"ior\": 1.6, \"absorption\": [0.1, 0.2, 0.4]},"
    " \"macro_clusters\": [{\"name\": \"one\", \"prototype\": {"
    "   \"trajectory\": [[0, 0, 0], [0, -1, 0.2], [0.1, -2, 0.3]],"
    "   \"a\": [0.2, 0.15, 0.1], \"b\": 0.1, \"twist\": [0, 1, 2],"
    "   \"shell\": {\"layers\": 4, \"st\": 9, \"su\": 5, \"core\": 0.3},"
    "   \"density\": {\"strands\": 40, \"seed\": 123456789012,"
    "     \"layout\": \"holes\", \"holes\": 2, \"hole_radius\": 0.1},"
    "   \"keys\": [{\"frame\": 0, \"a\": [0.3, 0.2, 0.1]},"
    "            {\"frame\": 5, \"trajectory\": [[0, 0, 0], [0, -1, 0],"
    "              [0, -2, 0.5]], \"twist\": [0, 2, 4]}]},"
    "  \"instances\": [{}, {\"translate\": [1, 0, 0], \"rotate\": {"
    "     \"axis\": [0, 1, 1], \"angle\": 30}, \"scale\": [1, 2, 1],"
    "     \"keys\": [{\"frame\": 0},"
    "              {\"frame\": 9, \"rotate\": {\"axis\": [0, 1, 1],"
    "               \"angle\": 75}}]},"
    "   {\"matrix\": [0, -1, 0, 2, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],"
    "    \"keys\": [{\"frame\": 1}, {\"frame\": 6, \"matrix\": [1, 0, 0, 2,"
    "     0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}]}]},"
    "  {\"prototype\": {\"trajectory\": [[1, 0, 0], [1, 1, 0]], \"a\": 0.2,"
    "   \"density\": {\"type\": \"vdb\", \"file\": \"hair.vdb\"}}}]}";

static void test_every_key_round_trips(void **state) {
  (void)state;
  satf_scene *scene, *again;
  satf_error err;
  const char *name = "/some/dir/keyed.json";
  if (satf_scene_parse(KEYED, strlen(KEYED), name, &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  assert_int_equal(satf_scene_warning_count(scene), 0);
  char *text, *text2;
  assert_int_equal(satf_scene_to_json(scene, "/some/dir", &text, &err),
                   SATF_OK);
  assert_non_null(strstr(text, "\"sub/db.exr\""));
  assert_non_null(strstr(text, "\"strands\":\t\"hair.strands.hair\""));
  assert_non_null(strstr(text, "\"hair.vdb\""));
  assert_non_null(strstr(text, "\"/abs/head.obj\""));
  assert_non_null(strstr(text, "\"model\":\t\"physical\""));
  assert_int_equal(scene->material.model, SATF_MATERIAL_PHYSICAL);
  assert_true(scene->material.has_absorption &&
              scene->material.absorption[2] == 0.4f &&
              scene->material.cuticle_tilt == -3.0f);
  if (satf_scene_parse(text, strlen(text), name, &again, &err) != SATF_OK)
    fail_msg("%s\n%s", text, err.message);
  if (!satf_scene_equal(scene, again))
    fail_msg("reads back different:\n%s", text);
  assert_int_equal(satf_scene_to_json(again, "/some/dir", &text2, &err),
                   SATF_OK);
  assert_string_equal(text, text2);
  for (double f = -3; f <= 31; f += 0.5)
    assert_same_at(scene, again, f);
  free(text);
  free(text2);
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
}

/* A scene built in memory, as the importer builds one. */
static void test_built_scene(void **state) {
  (void)state;
  satf_scene *scene, *again;
  satf_error err;
  char path[1024];
  test_path(path, sizeof path, "built.json");
  assert_int_equal(satf_scene_create(path, &scene, &err), SATF_OK);
  scene->macro_clusters = calloc(1, sizeof *scene->macro_clusters);
  scene->n_macro_clusters = 1;
  satf_scene_macro_cluster *mc = &scene->macro_clusters[0];
  satf_scene_cluster *c = &mc->prototype;
  static const float traj[6] = {0, 0, 0, 0.1f, -1, 0.2f};
  static const float moved[6] = {0, 0, 0, 0.3f, -1, 0.1f};
  static const float a2[2] = {0.25f, 0.125f};
  c->n_points = 2;
  c->trajectory = malloc(sizeof traj);
  memcpy(c->trajectory, traj, sizeof traj);
  satf_scene_curve *curves[3] = {&c->a, &c->b, &c->twist};
  for (int i = 0; i < 3; i++) {
    curves[i]->count = 2;
    curves[i]->values = malloc(sizeof a2);
    memcpy(curves[i]->values, a2, sizeof a2);
  }
  c->shell = (satf_scene_shell){3, 8, 16, 0.4f};
  c->density.strands = 100;
  c->density.seed = 3;
  c->density.strand_width = 0.05f;
  c->density.scale = 1.0f;
  /* What a file's reader gives the parameters of other layouts. */
  c->density.clumps = 8;
  c->density.clump_spread = 0.15f;
  c->density.holes = 4;
  c->density.hole_radius = 0.2f;
  c->density.gradient = 0.8f;
  mc->n_instances = 1;
  mc->instances = calloc(1, sizeof *mc->instances);
  for (int k = 0; k < 16; k += 5)
    mc->instances[0].m[k] = 1.0f;
  /* A mesh beside the file: the file names it "head.obj". */
  char mesh[1100];
  snprintf(mesh, sizeof mesh, "%s", path);
  strcpy(strrchr(mesh, '/') + 1, "head.obj");
  assert_int_equal(satf_scene_add_mesh(scene, mesh, &err), SATF_OK);
  /* The strands beside it too: "strands": "built.strands.hair". */
  scene->strands_file = malloc(strlen(path) + 32);
  strcpy(scene->strands_file, path);
  strcpy(strrchr(scene->strands_file, '/') + 1, "built.strands.hair");
  assert_int_equal(satf_scene_set_animation(scene, 24.0, 1, 3, &err), SATF_OK);
  assert_int_equal(
      satf_scene_add_prototype_key(scene, 0, 1, traj, NULL, NULL, NULL, &err),
      SATF_OK);
  assert_int_equal(
      satf_scene_add_prototype_key(scene, 0, 3, moved, a2, a2, a2, &err),
      SATF_OK);
  assert_int_not_equal(
      satf_scene_add_prototype_key(scene, 0, 2, moved, a2, a2, a2, &err),
      SATF_OK); /* frames must increase */
  assert_int_equal(satf_scene_write(scene, path, &err), SATF_OK);
  size_t size;
  unsigned char *bytes = test_read_file(path, &size);
  char *text = calloc(size + 1, 1);
  memcpy(text, bytes, size);
  free(bytes);
  assert_non_null(strstr(text, "\"file\":\t\"head.obj\""));
  assert_non_null(strstr(text, "\"strands\":\t\"built.strands.hair\""));
  free(text);
  if (satf_scene_load(path, &again, &err) != SATF_OK)
    fail_msg("%s", err.message);
  /* The camera of satf_scene_create is framed from no hair; the loaded one
   * from the hair: everything else is as built. */
  assert_false(satf_scene_camera_equal(&scene->camera, &again->camera));
  again->camera = scene->camera;
  assert_true(satf_scene_equal(scene, again));
  assert_true(satf_scene_prototype_is_animated(again, 0));
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
}

/* Scenes that travel: satf_scene_write names every file relative to the
 * scene's folder, with ../ steps (directories resolved, a link's own name
 * kept), except a file in another top-level tree. */
static void test_paths_relative_to_the_file(void **state) {
  (void)state;
  char base[1024], dir[1100], other[1100], path[1200], cmd[4096];
  test_path(base, sizeof base, "rel");
  snprintf(dir, sizeof dir, "%s/scenes/a", base);
  snprintf(other, sizeof other, "%s/assets", base);
  snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s' '%s'", base, dir,
           other);
  assert_int_equal(system(cmd), 0);
  snprintf(path, sizeof path, "%s/s.json", dir);
  satf_scene *scene;
  satf_error err;
  static const char json[] =
      "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, 0],"
      " [0, 1, 0]], \"a\": 0.5}}]}";
  assert_int_equal(satf_scene_parse(json, strlen(json), path, &scene, &err),
                   SATF_OK);
  char mesh[1200], hair[1200], db[1200];
  /* a sibling tree reached through "..", a file beside the scene, and a
   * file under another top-level directory */
  snprintf(mesh, sizeof mesh, "%s/../../assets/head.obj", dir);
  snprintf(hair, sizeof hair, "%s/s.strands.hair", dir);
  snprintf(db, sizeof db, "/usr/satf-no-such-db.exr");
  assert_int_equal(satf_scene_add_mesh(scene, mesh, &err), SATF_OK);
  assert_int_equal(satf_scene_set_database(scene, db, &err), SATF_OK);
  scene->strands_file = malloc(strlen(hair) + 1);
  strcpy(scene->strands_file, hair);
  assert_int_equal(satf_scene_write(scene, path, &err), SATF_OK);
  size_t size;
  unsigned char *bytes = test_read_file(path, &size);
  char *text = calloc(size + 1, 1);
  memcpy(text, bytes, size);
  free(bytes);
  if (!strstr(text, "\"file\":\t\"../../assets/head.obj\"") ||
      !strstr(text, "\"strands\":\t\"s.strands.hair\"") ||
      !strstr(text, "\"database\":\t\"/usr/satf-no-such-db.exr\""))
    fail_msg("paths not written relative to %s:\n%s", dir, text);
  free(text);
  satf_scene_destroy(scene);
}

static void test_too_many_lights(void **state) {
  (void)state;
  char json[2048] = "{\"macro_clusters\": [{\"prototype\": {\"trajectory\":"
                    " [[0, 0, 0], [0, 1, 0]], \"a\": 0.1}}], \"lights\": [";
  for (int i = 0; i <= SATF_SCENE_MAX_LIGHTS; i++)
    strcat(json,
           i ? ", {\"direction\": [0, 0, -1]}" : "{\"direction\": [0, 0, -1]}");
  strcat(json, "]}");
  satf_scene *scene;
  satf_error err;
  assert_int_equal(
      satf_scene_parse(json, strlen(json), "many.json", &scene, &err),
      SATF_ERR_ARGUMENT);
  assert_string_equal(err.message,
                      "many.json: lights: has 9 entries, expected 1 to 8");
}

/* A "tracks" density with its optional "ends" and "widths" reads back
 * the same; without "widths" (older scenes) every strand is strand_width
 * wide; a width out of range, or one too few, is refused. */
static const char TRACKED[] =
    "{\"macro_clusters\": [{\"prototype\": {"
    "  \"trajectory\": [[0, 0, 0], [0, -1, 0]], \"a\": 0.2, \"b\": 0.1,"
    "  \"density\": {\"type\": \"tracks\", \"slices\": 3,"
    "    \"strand_width\": 0.5, \"tracks\": [[0, 0.1, 0.2, 0.3, 0.4],"
    "      [1, -0.5, 0.5, -0.25, 0.25]],"
    "    \"ends\": [[0, 0.1, 0.2, 0.6, 0.3, 0.4], [0.3, -0.5, 0.5, 1, 0, 0]]"
    "    %s}}}]}";

static satf_status parse_tracked(const char *widths, satf_scene **out,
                                 satf_error *err) {
  char json[sizeof TRACKED + 64];
  snprintf(json, sizeof json, TRACKED, widths);
  return satf_scene_parse(json, strlen(json), "tracked.json", out, err);
}

static void test_track_widths_round_trip(void **state) {
  (void)state;
  satf_scene *scene, *again;
  satf_error err;
  if (parse_tracked(", \"widths\": [0.25, 1.75]", &scene, &err) != SATF_OK)
    fail_msg("%s", err.message);
  const satf_scene_density *d = &scene->macro_clusters[0].prototype.density;
  assert_int_equal(satf_scene_track_points(d), 2 + 2); /* two points each */
  assert_non_null(d->track_width);
  assert_float_equal(d->track_width[0], 0.25f, 0.0f);
  assert_float_equal(d->track_width[1], 1.75f, 0.0f);
  char *text;
  assert_int_equal(satf_scene_to_json(scene, NULL, &text, &err), SATF_OK);
  assert_non_null(strstr(text, "\"widths\""));
  if (satf_scene_parse(text, strlen(text), "again.json", &again, &err) !=
      SATF_OK)
    fail_msg("%s\n%s", text, err.message);
  if (!satf_scene_equal(scene, again))
    fail_msg("reads back different:\n%s", text);
  free(text);
  satf_scene_destroy(again);
  /* the same scene without widths is another scene */
  assert_int_equal(parse_tracked("", &again, &err), SATF_OK);
  assert_null(again->macro_clusters[0].prototype.density.track_width);
  assert_false(satf_scene_equal(scene, again));
  assert_int_equal(satf_scene_to_json(again, NULL, &text, &err), SATF_OK);
  assert_null(strstr(text, "\"widths\""));
  free(text);
  satf_scene_destroy(again);
  satf_scene_destroy(scene);
  assert_int_equal(parse_tracked(", \"widths\": [0.25, 2.5]", &scene, &err),
                   SATF_ERR_ARGUMENT);
  assert_non_null(strstr(err.message, "widths"));
  assert_int_not_equal(parse_tracked(", \"widths\": [0.25]", &scene, &err),
                       SATF_OK);
  assert_int_not_equal(parse_tracked(", \"widths\": [0, 1]", &scene, &err),
                       SATF_OK);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_samples_round_trip),
      cmocka_unit_test(test_every_key_round_trips),
      cmocka_unit_test(test_track_widths_round_trip),
      cmocka_unit_test(test_built_scene),
      cmocka_unit_test(test_too_many_lights),
      cmocka_unit_test(test_paths_relative_to_the_file),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
