/* scene_write.c - the one writer of the scene format (samples/README.md):
 * a satf_scene, keyframes included, as JSON text that satf_scene_parse
 * reads back into the same scene. Every value is written, defaults too, so
 * the file says what the renderer will use; the exceptions are what the
 * format derives: an automatic camera position, unused layout parameters
 * and, in keys, values a key takes from the static object. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <cjson/cJSON.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "satf/common.h"
#include "scene_anim.h"
#include "scene_check.h"
#include "scene_fields.h"

typedef struct writer {
  const char *base_dir; /* paths under it are written relative to it */
  char *cwd;            /* when set, other relative paths become absolute */
  const char *real_dir; /* satf_scene_write: the file's canonical directory */
  int failed;           /* out of memory */
  char path_buf[4096];  /* a path being written */
} writer;

/* ---- numbers: the shortest text that reads back to the same bits ---- */

static cJSON *raw(writer *w, const char *text) {
  cJSON *item = cJSON_CreateRaw(text);
  if (!item)
    w->failed = 1;
  return item;
}

/* Whole numbers print as such ("80", not "8e+01"). */
static void plain_integer(char *buf, size_t size, double v) {
  if (strchr(buf, 'e') && v == floor(v) && fabs(v) < 1e15)
    snprintf(buf, size, "%.0f", v);
}

static cJSON *num_float(writer *w, float f) {
  char buf[48];
  for (int digits = 1; digits <= 9; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, (double)f);
    float back = (float)strtod(buf, NULL);
    if (memcmp(&back, &f, sizeof f) == 0)
      break;
  }
  plain_integer(buf, sizeof buf, f);
  return raw(w, buf);
}

static cJSON *num_double(writer *w, double d) {
  char buf[48];
  for (int digits = 1; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, d);
    double back = strtod(buf, NULL);
    if (memcmp(&back, &d, sizeof d) == 0)
      break;
  }
  plain_integer(buf, sizeof buf, d);
  return raw(w, buf);
}

static cJSON *num_int(writer *w, long long v) {
  char buf[32];
  snprintf(buf, sizeof buf, "%lld", v);
  return raw(w, buf);
}

static cJSON *floats(writer *w, const float *v, int n) {
  cJSON *a = cJSON_CreateArray();
  if (!a)
    w->failed = 1;
  for (int i = 0; a && i < n; i++)
    cJSON_AddItemToArray(a, num_float(w, v[i]));
  return a;
}

/* A curve: one number for a constant, else its control values. */
static cJSON *curve(writer *w, const float *v, int n) {
  return n == 1 ? num_float(w, v[0]) : floats(w, v, n);
}

/* The parser normalizes directions and up vectors, and normalizing a unit
 * vector again can move its last bit: write a vector whose normalization
 * is the stored one. A scaled copy nearly always is; the search is short. */
static void unit_source(const float unit[3], float out[3]) {
  for (int s = 0; s <= 20000; s++) {
    double scale = 1.0 + s / 1024.0;
    for (int k = 0; k < 3; k++)
      out[k] = (float)(unit[k] * scale);
    float back[3];
    memcpy(back, out, sizeof back);
    scene_normalize(back, scene_vec_length(back));
    if (memcmp(back, unit, sizeof back) == 0)
      return;
  }
  memcpy(out, unit, 3 * sizeof *out);
}

static cJSON *unit_vector(writer *w, const float unit[3]) {
  float v[3];
  unit_source(unit, v);
  return floats(w, v, 3);
}

static void add(writer *w, cJSON *obj, const char *key, cJSON *item) {
  if (!item || !cJSON_AddItemToObject(obj, key, item)) {
    cJSON_Delete(item);
    w->failed = 1;
  }
}

static void add_string(writer *w, cJSON *obj, const char *key,
                       const char *text) {
  add(w, obj, key, cJSON_CreateString(text));
}

static void add_bool(writer *w, cJSON *obj, const char *key, int value) {
  add(w, obj, key, cJSON_CreateBool(value));
}

static cJSON *object(writer *w) {
  cJSON *o = cJSON_CreateObject();
  if (!o)
    w->failed = 1;
  return o;
}

static cJSON *array(writer *w) {
  cJSON *a = cJSON_CreateArray();
  if (!a)
    w->failed = 1;
  return a;
}

static void append(writer *w, cJSON *arr, cJSON *item) {
  if (!arr || !item || !cJSON_AddItemToArray(arr, item)) {
    cJSON_Delete(item);
    w->failed = 1;
  }
}

/* The absolute form of path with its directory canonical (symlinks and
 * "..", resolved by realpath) and its own name kept, so a file that is a
 * link beside the scene is named as the link; 0 when the directory does
 * not resolve. */
static int canonical(const char *path, char *out) {
  const char *slash = strrchr(path, '/');
  const char *name = slash ? slash + 1 : path;
  if (!*name || !strcmp(name, ".") || !strcmp(name, ".."))
    return realpath(path, out) != NULL;
  char buf[PATH_MAX], dir[PATH_MAX];
  snprintf(buf, sizeof buf, "%.*s", slash ? (int)(slash - path) : 1,
           slash ? (slash == path ? "/" : path) : ".");
  if (!realpath(buf, dir))
    return 0;
  int n =
      snprintf(out, PATH_MAX, "%s%s%s", dir, strcmp(dir, "/") ? "/" : "", name);
  return n > 0 && n < PATH_MAX;
}

/* path relative to the canonical directory real_dir (with "../" steps),
 * into out; 0 when it cannot be found or the two share no directory below
 * the root (a file in another top-level tree, e.g. /usr/share, keeps its
 * absolute name: it stays put when the scene's folder moves). */
static int relative_to(const char *real_dir, const char *path, char *out,
                       size_t size) {
  char target[PATH_MAX];
  if (!canonical(path, target))
    return 0;
  size_t common = 0; /* length of the shared leading directories */
  for (size_t i = 0;; i++) {
    int dir_end = real_dir[i] == '\0' || real_dir[i] == '/';
    if (dir_end && (target[i] == '/' || target[i] == '\0'))
      common = i;
    if (real_dir[i] == '\0' || real_dir[i] != target[i])
      break;
  }
  if (!strcmp(real_dir, "/")) {
    int n = snprintf(out, size, "%s", target + 1);
    return n > 0 && (size_t)n < size;
  }
  if (common == 0)
    return 0;
  size_t at = 0;
  for (const char *p = real_dir + common; *p; p++)
    if (*p == '/' && at + 3 < size) {
      memcpy(out + at, "../", 3);
      at += 3;
    }
  const char *rest = target + common + (target[common] == '/');
  int n = snprintf(out + at, size - at, "%s", rest);
  return n >= 0 && (size_t)n < size - at && out[0];
}

/* A path as the file should name it (see satf_scene_write). */
static void add_path(writer *w, cJSON *obj, const char *key, const char *path) {
  size_t n = w->base_dir ? strlen(w->base_dir) : 0;
  if (w->real_dir &&
      relative_to(w->real_dir, path, w->path_buf, sizeof w->path_buf)) {
    add_string(w, obj, key, w->path_buf);
  } else if (n && strncmp(path, w->base_dir, n) == 0 &&
             (path[n] == '/' || w->base_dir[n - 1] == '/') && path[n]) {
    add_string(w, obj, key, path + n + (path[n] == '/'));
  } else if (w->cwd && path[0] != '/') {
    snprintf(w->path_buf, sizeof w->path_buf, "%s/%s", w->cwd, path);
    add_string(w, obj, key, w->path_buf);
  } else {
    add_string(w, obj, key, path);
  }
}

/* ---- the simple fields, from their tables (scene_fields.h) ---- */

/* Writes an OTHER row of a table (nothing for a key the format derives). */
typedef void (*write_other_fn)(writer *w, cJSON *o, const scene_field *row,
                               const void *base);

/* Adds t's keys of base to o in the table's order: the simple rows as
 * numbers, flags and arrays, the OTHER rows through other. A row of
 * another layout than layout (only_layout) would only draw a warning, and
 * an above_default row not above its default means "unset" (a scene made
 * in memory may hold 0 there): neither is written. */
static void add_fields(writer *w, cJSON *o, const scene_table *t,
                       const void *base, int layout, write_other_fn other) {
  for (int i = 0; i < t->n; i++) {
    const scene_field *row = &t->fields[i];
    const void *at = scene_field_at_const(row, base);
    if (row->only_layout != 0 && row->only_layout != 1 + layout)
      continue;
    switch (row->type) {
    case SCENE_FIELD_FLOAT:
      if (!row->above_default || *(const float *)at > (float)row->def)
        add(w, o, row->key, num_float(w, *(const float *)at));
      break;
    case SCENE_FIELD_INT:
      if (!row->above_default || *(const int *)at > (int)row->def)
        add(w, o, row->key, num_int(w, *(const int *)at));
      break;
    case SCENE_FIELD_BOOL: add_bool(w, o, row->key, *(const int *)at); break;
    case SCENE_FIELD_VEC3: add(w, o, row->key, floats(w, at, 3)); break;
    case SCENE_FIELD_OTHER:
      if (other)
        other(w, o, row, base);
      break;
    }
  }
}

/* ---- the hair ---- */

static cJSON *shell(writer *w, const satf_scene_shell *s) {
  cJSON *o = object(w);
  add_fields(w, o, &SCENE_SHELL, s, -1, NULL);
  return o;
}

/* The keys of the tracks density that are more than a number. */
static void tracks_other(writer *w, cJSON *o, const scene_field *row,
                         const void *base) {
  const satf_scene_density *d = base;
  if (strcmp(row->key, "type") == 0) {
    add_string(w, o, "type", "tracks");
  } else if (strcmp(row->key, "slices") == 0) {
    add(w, o, "slices", num_int(w, d->track_slices));
  } else if (strcmp(row->key, "tracks") == 0) {
    cJSON *tracks = array(w);
    const float *xy = d->track_xy;
    for (int k = 0; k < d->n_tracks; k++) {
      cJSON *t = array(w);
      append(w, t, num_int(w, d->track_first[k]));
      for (int i = 0; i < 2 * d->track_count[k]; i++)
        append(w, t, num_float(w, xy[i]));
      xy += 2 * d->track_count[k];
      append(w, tracks, t);
    }
    add(w, o, "tracks", tracks);
  } else if (strcmp(row->key, "ends") == 0 && d->track_ends) {
    cJSON *ends = array(w);
    for (int k = 0; k < d->n_tracks; k++) {
      cJSON *e = array(w);
      for (int i = 0; i < 6; i++)
        append(w, e, num_float(w, d->track_ends[6 * k + i]));
      append(w, ends, e);
    }
    add(w, o, "ends", ends);
  } else if (strcmp(row->key, "widths") == 0 && d->track_width) {
    cJSON *widths = array(w);
    for (int k = 0; k < d->n_tracks; k++)
      append(w, widths, num_float(w, d->track_width[k]));
    add(w, o, "widths", widths);
  }
}

/* The keys of the procedural density that are more than a number. */
static void procedural_other(writer *w, cJSON *o, const scene_field *row,
                             const void *base) {
  const satf_scene_density *d = base;
  if (strcmp(row->key, "type") == 0)
    add_string(w, o, "type", "procedural");
  else if (strcmp(row->key, "seed") == 0)
    add(w, o, "seed", num_int(w, (long long)d->seed));
  else if (strcmp(row->key, "layout") == 0)
    add_string(w, o, "layout", satf_scene_layout_name(d->layout));
}

static cJSON *density(writer *w, const satf_scene_density *d) {
  cJSON *o = object(w);
  if (d->type == SATF_SCENE_DENSITY_VDB) {
    add_string(w, o, "type", "vdb");
    add_path(w, o, "file", d->vdb_file);
    add_string(w, o, "grid", d->vdb_grid ? d->vdb_grid : "density");
  } else if (d->type == SATF_SCENE_DENSITY_TRACKS) {
    add_fields(w, o, &SCENE_TRACKS, d, -1, tracks_other);
  } else {
    /* the parameters of other layouts would only draw warnings */
    add_fields(w, o, &SCENE_PROCEDURAL, d, (int)d->layout, procedural_other);
  }
  return o;
}

static cJSON *trajectory(writer *w, const float *points, int n) {
  cJSON *a = array(w);
  for (int i = 0; i < n; i++)
    append(w, a, floats(w, points + 3 * i, 3));
  return a;
}

static cJSON *prototype_keys(writer *w, const scene_track *t,
                             const satf_scene_cluster *c) {
  const scene_proto_key *keys = t->keys;
  cJSON *a = array(w);
  for (int k = 0; k < t->n_keys; k++) {
    cJSON *o = object(w);
    add(w, o, "frame", num_double(w, t->frames[k]));
    if (keys[k].trajectory)
      add(w, o, "trajectory", trajectory(w, keys[k].trajectory, c->n_points));
    if (keys[k].a)
      add(w, o, "a", curve(w, keys[k].a, c->a.count));
    if (keys[k].b)
      add(w, o, "b", curve(w, keys[k].b, c->b.count));
    if (keys[k].twist)
      add(w, o, "twist", curve(w, keys[k].twist, c->twist.count));
    append(w, a, o);
  }
  return a;
}

static cJSON *cluster(writer *w, const satf_scene_cluster *c,
                      const scene_track *keys) {
  cJSON *o = object(w);
  add(w, o, "trajectory", trajectory(w, c->trajectory, c->n_points));
  add(w, o, "a", curve(w, c->a.values, c->a.count));
  add(w, o, "b", curve(w, c->b.values, c->b.count));
  add(w, o, "twist", curve(w, c->twist.values, c->twist.count));
  add(w, o, "shell", shell(w, &c->shell));
  add(w, o, "density", density(w, &c->density));
  if (keys && keys->n_keys > 0)
    add(w, o, "keys", prototype_keys(w, keys, c));
  return o;
}

/* ---- transforms ---- */

static int is_identity(const float m[16]) {
  for (int k = 0; k < 16; k++) {
    float one = k % 5 == 0 ? 1.0f : 0.0f;
    if (memcmp(&m[k], &one, sizeof one) != 0)
      return 0;
  }
  return 1;
}

static int same_floats(const float *a, const float *b, int n) {
  return memcmp(a, b, (size_t)n * sizeof *a) == 0;
}

/* The parts of f that differ from def (the static transform for a key, the
 * identity for the static transform itself). */
static void add_xform(writer *w, cJSON *o, const scene_xform *f,
                      const scene_xform *def) {
  if (f->is_matrix) {
    add(w, o, "matrix", floats(w, f->m, 16));
    return;
  }
  if (!same_floats(f->translate, def->translate, 3))
    add(w, o, "translate", floats(w, f->translate, 3));
  if (!same_floats(f->axis, def->axis, 3) ||
      memcmp(&f->degrees, &def->degrees, sizeof f->degrees) != 0) {
    cJSON *r = object(w);
    add(w, r, "axis", floats(w, f->axis, 3));
    add(w, r, "angle", num_double(w, f->degrees));
    add(w, o, "rotate", r);
  }
  if (!same_floats(f->scale, def->scale, 3))
    add(w, o, "scale", floats(w, f->scale, 3));
}

static const scene_xform IDENTITY = {
    0,         {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
    {0, 0, 0}, {0, 0, 1},
    0.0,       {1, 1, 1}};

static cJSON *animated_instance(writer *w, const scene_instance_track *t) {
  cJSON *o = object(w);
  add_xform(w, o, &t->base, &IDENTITY);
  const scene_xform_key *keys = t->track.keys;
  cJSON *a = array(w);
  for (int k = 0; k < t->track.n_keys; k++) {
    cJSON *key = object(w);
    add(w, key, "frame", num_double(w, t->track.frames[k]));
    add_xform(w, key, &keys[k].form, &t->base);
    append(w, a, key);
  }
  add(w, o, "keys", a);
  return o;
}

static cJSON *instances(writer *w, const satf_scene *scene, int m, int *track) {
  const satf_scene_animation *anim = scene->animation;
  const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
  cJSON *a = array(w);
  for (int i = 0; i < mc->n_instances; i++) {
    /* Tracks are in file order: (macro-cluster, instance) increasing. */
    const scene_instance_track *t = NULL;
    if (anim && *track < anim->n_instance_tracks &&
        anim->instances[*track].macro_cluster == m &&
        anim->instances[*track].instance == i)
      t = &anim->instances[(*track)++];
    if (t) {
      append(w, a, animated_instance(w, t));
      continue;
    }
    cJSON *o = object(w);
    if (!is_identity(mc->instances[i].m))
      add(w, o, "matrix", floats(w, mc->instances[i].m, 16));
    append(w, a, o);
  }
  return a;
}

static cJSON *macro_clusters(writer *w, const satf_scene *scene) {
  const satf_scene_animation *anim = scene->animation;
  cJSON *a = array(w);
  int track = 0;
  for (int m = 0; m < scene->n_macro_clusters; m++) {
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[m];
    const scene_track *keys =
        anim && m < anim->n_protos ? &anim->protos[m] : NULL;
    cJSON *o = object(w);
    if (mc->name)
      add_string(w, o, "name", mc->name);
    add(w, o, "prototype", cluster(w, &mc->prototype, keys));
    add(w, o, "instances", instances(w, scene, m, &track));
    append(w, a, o);
  }
  return a;
}

/* ---- camera, lights and the rest ---- */

static cJSON *camera_keys(writer *w, const scene_track *t) {
  const scene_camera_key *keys = t->keys;
  cJSON *a = array(w);
  for (int k = 0; k < t->n_keys; k++) {
    cJSON *o = object(w);
    add(w, o, "frame", num_double(w, t->frames[k]));
    if (keys[k].given & SCENE_GIVES_POSITION)
      add(w, o, "position", floats(w, keys[k].position, 3));
    if (keys[k].given & SCENE_GIVES_TARGET)
      add(w, o, "target", floats(w, keys[k].target, 3));
    if (keys[k].given & SCENE_GIVES_UP)
      add(w, o, "up", unit_vector(w, keys[k].up));
    if (keys[k].given & SCENE_GIVES_FOV)
      add(w, o, "fov_y", num_float(w, keys[k].fov_y));
    append(w, a, o);
  }
  return a;
}

static cJSON *camera(writer *w, const satf_scene *scene) {
  const satf_scene_camera *c = &scene->camera;
  cJSON *o = object(w);
  if (!c->automatic) /* else framed from the bounds again when read */
    add(w, o, "position", floats(w, c->position, 3));
  add(w, o, "target", floats(w, c->target, 3));
  add(w, o, "up", unit_vector(w, c->up));
  add(w, o, "fov_y", num_float(w, c->fov_y));
  if (c->near_clip > 0.0f) /* 0: the renderer picks */
    add(w, o, "near", num_float(w, c->near_clip));
  if (c->far_clip > 0.0f)
    add(w, o, "far", num_float(w, c->far_clip));
  if (scene->animation && scene->animation->camera.n_keys > 0)
    add(w, o, "keys", camera_keys(w, &scene->animation->camera));
  return o;
}

static cJSON *light_keys(writer *w, const scene_track *t, int point) {
  const scene_light_key *keys = t->keys;
  cJSON *a = array(w);
  for (int k = 0; k < t->n_keys; k++) {
    cJSON *o = object(w);
    add(w, o, "frame", num_double(w, t->frames[k]));
    if (keys[k].given & SCENE_GIVES_VECTOR)
      add(w, o, point ? "position" : "direction",
          point ? floats(w, keys[k].vector, 3)
                : unit_vector(w, keys[k].vector));
    if (keys[k].given & SCENE_GIVES_COLOR)
      add(w, o, "color", floats(w, keys[k].color, 3));
    if (keys[k].given & SCENE_GIVES_INTENSITY)
      add(w, o, "intensity", num_float(w, keys[k].intensity));
    append(w, a, o);
  }
  return a;
}

static cJSON *lights(writer *w, const satf_scene *scene) {
  const satf_scene_animation *anim = scene->animation;
  cJSON *a = array(w);
  for (int i = 0; i < scene->n_lights; i++) {
    const satf_scene_light *l = &scene->lights[i];
    int point = l->type == SATF_SCENE_LIGHT_POINT;
    cJSON *o = object(w);
    add_string(w, o, "type", point ? "point" : "directional");
    if (point)
      add(w, o, "position", floats(w, l->position, 3));
    else
      add(w, o, "direction", unit_vector(w, l->direction));
    add(w, o, "color", floats(w, l->color, 3));
    add(w, o, "intensity", num_float(w, l->intensity));
    if (anim && i < anim->n_lights && anim->lights[i].n_keys > 0)
      add(w, o, "keys", light_keys(w, &anim->lights[i], point));
    append(w, a, o);
  }
  return a;
}

/* The material's keys that are more than a number ("shift" is only the
 * default of shift_I and shift_II, which are written). */
static void material_other(writer *w, cJSON *o, const scene_field *row,
                           const void *base) {
  static const char *const models[] = {"kk", "physical"};
  const satf_scene_material *m = base;
  if (strcmp(row->key, "shift_I") == 0)
    add(w, o, "shift_I", num_float(w, m->shift_I));
  else if (strcmp(row->key, "shift_II") == 0)
    add(w, o, "shift_II", num_float(w, m->shift_II));
  else if (strcmp(row->key, "model") == 0)
    add_string(w, o, "model", models[m->model]);
  else if (strcmp(row->key, "absorption") == 0 && m->has_absorption)
    add(w, o, "absorption", floats(w, m->absorption, 3));
}

static cJSON *material(writer *w, const satf_scene_material *m) {
  cJSON *o = object(w);
  add_fields(w, o, &SCENE_MATERIAL, m, -1, material_other);
  return o;
}

static cJSON *effects(writer *w, const satf_scene_effects *e) {
  cJSON *o = object(w);
  add_fields(w, o, &SCENE_EFFECTS, e, -1, NULL);
  return o;
}

static cJSON *meshes(writer *w, const satf_scene *scene) {
  cJSON *a = array(w);
  for (int i = 0; i < scene->n_meshes; i++) {
    const satf_scene_mesh *mesh = &scene->meshes[i];
    cJSON *o = object(w);
    add_path(w, o, "file", mesh->file);
    add(w, o, "color", floats(w, mesh->color, 3));
    if (!is_identity(mesh->m)) {
      cJSON *t = object(w);
      add(w, t, "matrix", floats(w, mesh->m, 16));
      add(w, o, "transform", t);
    }
    append(w, a, o);
  }
  return a;
}

static cJSON *animation(writer *w, const satf_scene_animation *anim) {
  cJSON *o = object(w), *frames = array(w);
  add(w, o, "fps", num_double(w, anim->fps));
  append(w, frames, num_int(w, anim->first));
  append(w, frames, num_int(w, anim->last));
  add(w, o, "frames", frames);
  return o;
}

static cJSON *image(writer *w, const satf_scene_image *im) {
  cJSON *o = object(w);
  add_fields(w, o, &SCENE_IMAGE, im, -1, NULL); /* samples: when not 1 */
  return o;
}

static cJSON *root(writer *w, const satf_scene *scene) {
  cJSON *o = object(w);
  if (!o)
    return NULL;
  if (scene->description)
    add_string(w, o, "description", scene->description);
  if (scene->animation)
    add(w, o, "animation", animation(w, scene->animation));
  if (scene->database)
    add_path(w, o, "database", scene->database);
  if (scene->strands_file)
    add_path(w, o, "strands", scene->strands_file);
  if (scene->n_meshes > 0)
    add(w, o, "meshes", meshes(w, scene));
  add(w, o, "image", image(w, &scene->image));
  add(w, o, "camera", camera(w, scene));
  add(w, o, "lights", lights(w, scene));
  add(w, o, "background", floats(w, scene->background, 3));
  add(w, o, "material", material(w, &scene->material));
  add(w, o, "effects", effects(w, &scene->effects));
  add(w, o, "macro_clusters", macro_clusters(w, scene));
  return o;
}

static satf_status to_json(const satf_scene *scene, writer *w, char **json,
                           satf_error *err) {
  const char *name = scene && scene->name ? scene->name : "<scene>";
  if (!json || !scene)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_to_json: no scene or no output");
  *json = NULL;
  cJSON *tree = root(w, scene);
  char *text = tree && !w->failed ? cJSON_Print(tree) : NULL;
  cJSON_Delete(tree);
  if (!text)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  *json = text;
  return SATF_OK;
}

satf_status satf_scene_to_json(const satf_scene *scene, const char *base_dir,
                               char **json, satf_error *err) {
  writer w = {.base_dir = base_dir};
  return to_json(scene, &w, json, err);
}

satf_status satf_scene_write(const satf_scene *scene, const char *path,
                             satf_error *err) {
  if (!path)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "satf_scene_write: no path");
  writer w = {0};
  char *dir = NULL, cwd[4096];
  const char *slash = strrchr(path, '/');
  if (slash) {
    size_t n = slash == path ? 1 : (size_t)(slash - path);
    dir = malloc(n + 1);
    if (!dir)
      return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
    memcpy(dir, path, n);
    dir[n] = '\0';
    /* Relative paths outside the file's directory: name them absolutely,
     * since the file's reader resolves them against that directory. */
    if (getcwd(cwd, sizeof cwd))
      w.cwd = cwd;
  }
  w.base_dir = dir;
  /* Every path relative to the file's directory (satf/scene.h). */
  char real_dir[PATH_MAX];
  if (realpath(dir ? dir : ".", real_dir))
    w.real_dir = real_dir;
  char *text = NULL;
  satf_status s = to_json(scene, &w, &text, err);
  if (s == SATF_OK)
    s = satf_write_file_atomic(path, text, strlen(text), err);
  free(text);
  free(dir);
  return s;
}
