/* scene_parse_cluster.c - the hair part of the scene schema
 * (samples/README.md): macro-clusters (SATF sec. 3.1; their instance
 * transforms are scene_parse_instance.c), the generalized-disk prototype
 * cluster (eq. 1-3) with its keys, and its density (sec. 3.3). */
#include "scene_parse_cluster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_check.h"
#include "scene_fields.h"
#include "scene_parse_instance.h"
#include "scene_transform.h"

static const scene_range R_COORD = {-SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD,
                                    0, 0};
static const scene_range R_RADIUS = {0, SATF_SCENE_MAX_COORD, 1, 0};
static const scene_range R_TWIST = {-1e4, 1e4, 0, 0};

/* ---- cluster (SATF eq. 1-3) ---- */

/* A 1-D B-spline: one number (a constant) or an array of control values. */
static satf_status parse_curve(scene_ctx *ctx, const cJSON *obj,
                               const char *key, const scene_range *range,
                               int required, double def,
                               satf_scene_curve *out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  if (!item && required)
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT, "missing required key");
  if (item && !cJSON_IsNumber(item) && !cJSON_IsArray(item))
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                          "expected a number or an array of numbers, got %s",
                          scene_type_name(item));
  int count = 1;
  if (item && cJSON_IsArray(item)) {
    count = cJSON_GetArraySize(item);
    if (count < 1 || count > SATF_SCENE_MAX_CONTROL_POINTS)
      return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT,
                            "has %d control values, expected 1 to %d", count,
                            SATF_SCENE_MAX_CONTROL_POINTS);
  }
  out->values = malloc((size_t)count * sizeof *out->values);
  if (!out->values)
    return scene_nomem(ctx);
  out->count = count;
  if (!item) {
    out->values[0] = (float)def;
    return SATF_OK;
  }
  size_t previous = scene_push_key(ctx, key);
  satf_status s = SATF_OK;
  double v;
  if (cJSON_IsNumber(item)) {
    s = scene_number(ctx, item, range, &v);
    out->values[0] = (float)v;
  } else {
    int i = 0;
    for (const cJSON *e = item->child; e && s == SATF_OK; e = e->next, i++) {
      size_t inner = scene_push_index(ctx, i);
      s = scene_number(ctx, e, range, &v);
      out->values[i] = (float)v;
      scene_pop(ctx, inner);
    }
  }
  scene_pop(ctx, previous);
  return s;
}

static satf_status copy_curve(scene_ctx *ctx, const satf_scene_curve *from,
                              satf_scene_curve *to) {
  to->values = malloc((size_t)from->count * sizeof *to->values);
  if (!to->values)
    return scene_nomem(ctx);
  memcpy(to->values, from->values, (size_t)from->count * sizeof *to->values);
  to->count = from->count;
  return SATF_OK;
}

static satf_status parse_cluster_curve(scene_ctx *ctx, const cJSON *obj,
                                       const char *key, satf_scene_curve *out) {
  int twist = strcmp(key, "twist") == 0;
  return parse_curve(ctx, obj, key, twist ? &R_TWIST : &R_RADIUS, !twist, 0.0,
                     out);
}

static satf_status parse_trajectory(scene_ctx *ctx, const cJSON *obj,
                                    satf_scene_cluster *c) {
  const cJSON *arr;
  int n;
  satf_status s = scene_key_array(ctx, obj, "trajectory", 1, 2,
                                  SATF_SCENE_MAX_CONTROL_POINTS, &arr, &n);
  if (s != SATF_OK)
    return s;
  c->trajectory = malloc((size_t)n * 3 * sizeof *c->trajectory);
  if (!c->trajectory)
    return scene_nomem(ctx);
  c->n_points = n;
  size_t previous = scene_push_key(ctx, "trajectory");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    s = scene_vec(ctx, e, 3, &R_COORD, c->trajectory + 3 * i);
    scene_pop(ctx, inner);
  }
  /* A curve that never leaves its first point has no tangent, so no normal
   * plane to sweep the ellipse in (SATF sec. 3.2). */
  if (s == SATF_OK && !(scene_trajectory_extent(c->trajectory, n) > 1e-6))
    s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                   "all %d control points coincide; the trajectory needs a "
                   "length",
                   n);
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_shell(scene_ctx *ctx, const cJSON *cluster,
                               satf_scene_shell *shell) {
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, cluster, "shell", 0, &obj);
  if (s != SATF_OK)
    return s;
  static const cJSON empty = {0};
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "shell");
  s = scene_fields_read(ctx, obj, &SCENE_SHELL, shell, NULL, NULL);
  scene_pop(ctx, previous);
  return s;
}

static const char *const layout_names[SATF_SCENE_LAYOUT_COUNT] = {
    "uniform", "clumped", "gradient", "holes"};

const char *satf_scene_layout_name(satf_scene_layout layout) {
  return (layout >= 0 && layout < SATF_SCENE_LAYOUT_COUNT)
             ? layout_names[layout]
             : "unknown";
}

/* The procedural density's keys that are more than a number: its seed (up
 * to 2^53) and layout; its type chose this reader. */
typedef struct procedural_other {
  double seed;
  int layout;
} procedural_other;

static satf_status read_procedural_other(scene_ctx *ctx, const cJSON *obj,
                                         const scene_field *row, void *base,
                                         void *user) {
  procedural_other *o = user;
  (void)base;
  if (strcmp(row->key, "seed") == 0)
    return scene_key_number(ctx, obj, row->key, &row->range, 0, 1, &o->seed);
  if (strcmp(row->key, "layout") == 0)
    return scene_key_enum(ctx, obj, row->key, layout_names,
                          SATF_SCENE_LAYOUT_COUNT, SATF_SCENE_LAYOUT_UNIFORM,
                          &o->layout);
  return SATF_OK;
}

static satf_status parse_procedural(scene_ctx *ctx, const cJSON *obj,
                                    satf_scene_density *d) {
  procedural_other o = {0};
  satf_status s = scene_fields_read(ctx, obj, &SCENE_PROCEDURAL, d,
                                    read_procedural_other, &o);
  if (s != SATF_OK)
    return s;
  d->seed = (uint64_t)o.seed;
  d->layout = (satf_scene_layout)o.layout;
  /* Layout parameters given for a layout that does not use them are almost
   * certainly a mistake in the file; say so. */
  return scene_fields_warn_unused(ctx, obj, &SCENE_PROCEDURAL, d->layout,
                                  layout_names);
}

/* One track: [first slice, x0, y0, x1, y1, ...]; its pairs go to xy. */
static satf_status parse_track(scene_ctx *ctx, const cJSON *item, int slices,
                               int *first, int *count, float *xy) {
  static const scene_range r_coord = {-8, 8, 0, 0};
  int n = cJSON_IsArray(item) ? cJSON_GetArraySize(item) : 0;
  if (n < 3 || n % 2 == 0)
    return scene_fail(ctx, SATF_ERR_FORMAT,
                      "expected [first slice, x, y, x, y, ...], got %s of %d",
                      scene_type_name(item), n);
  const cJSON *e = item->child;
  double f;
  static const scene_range r_first = {0, SATF_SCENE_MAX_TRACK_SLICES, 0, 1};
  satf_status s = scene_number(ctx, e, &r_first, &f);
  if (s != SATF_OK)
    return s;
  *first = (int)f;
  *count = (n - 1) / 2;
  if (*first + *count > slices)
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "slices %d to %d: the density has %d slices", *first,
                      *first + *count - 1, slices);
  int i = 0;
  for (e = e->next; e; e = e->next, i++) {
    double v;
    if ((s = scene_number(ctx, e, &r_coord, &v)) != SATF_OK)
      return s;
    xy[i] = (float)v;
  }
  return SATF_OK;
}

/* "ends": per track, (t, x, y) of its strand's root and tip, the lower t
 * first (satf/scene.h). */
static satf_status parse_ends(scene_ctx *ctx, const cJSON *obj,
                              satf_scene_density *d) {
  static const scene_range r_coord = {-8, 8, 0, 0};
  const cJSON *arr;
  int n = 0;
  satf_status s =
      scene_key_array(ctx, obj, "ends", 0, d->n_tracks, d->n_tracks, &arr, &n);
  if (s != SATF_OK || !arr)
    return s;
  d->track_ends = malloc(6 * (size_t)n * sizeof(float) + 1);
  if (!d->track_ends)
    return scene_nomem(ctx);
  size_t previous = scene_push_key(ctx, "ends");
  int k = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, k++) {
    size_t item = scene_push_index(ctx, k);
    float *v = d->track_ends + 6 * (size_t)k;
    s = scene_vec(ctx, e, 6, &r_coord, v);
    if (s == SATF_OK && !(v[0] >= 0.0f && v[0] <= v[3] && v[3] <= 1.0f))
      s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                     "expected [t, x, y, t, x, y] with 0 <= t <= t <= 1, "
                     "got t %g and %g",
                     (double)v[0], (double)v[3]);
    scene_pop(ctx, item);
  }
  scene_pop(ctx, previous);
  return s;
}

/* "widths": per track, its strand's diameter in cluster radii, in the
 * range of strand_width (satf/scene.h). */
static satf_status parse_widths(scene_ctx *ctx, const cJSON *obj,
                                satf_scene_density *d) {
  static const scene_range r_width = {0, 2, 1, 0};
  const cJSON *arr;
  int n = 0;
  satf_status s = scene_key_array(ctx, obj, "widths", 0, d->n_tracks,
                                  d->n_tracks, &arr, &n);
  if (s != SATF_OK || !arr)
    return s;
  d->track_width = malloc((size_t)n * sizeof(float) + 1);
  if (!d->track_width)
    return scene_nomem(ctx);
  size_t previous = scene_push_key(ctx, "widths");
  int k = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, k++) {
    size_t item = scene_push_index(ctx, k);
    double v;
    s = scene_number(ctx, e, &r_width, &v);
    d->track_width[k] = (float)v;
    scene_pop(ctx, item);
  }
  scene_pop(ctx, previous);
  return s;
}

/* "tracks": the cluster's own strands in its normalised cross-section. */
/* The tracks' slice count, required (the other OTHER rows of
 * SCENE_TRACKS are read after the walk). */
static satf_status read_slices(scene_ctx *ctx, const cJSON *obj,
                               const scene_field *row, void *base, void *user) {
  (void)base;
  if (strcmp(row->key, "slices") != 0)
    return SATF_OK;
  return scene_key_number(ctx, obj, row->key, &row->range, 1, 0, user);
}

static satf_status parse_tracks(scene_ctx *ctx, const cJSON *obj,
                                satf_scene_density *d) {
  const cJSON *arr;
  int n = 0;
  double slices = 0;
  satf_status s;
  /* slices, strand_width and scale; then the tracks, ends and widths */
  if ((s = scene_fields_read(ctx, obj, &SCENE_TRACKS, d, read_slices,
                             &slices)) != SATF_OK ||
      (s = scene_key_array(ctx, obj, "tracks", 1, 1, SATF_SCENE_MAX_STRANDS,
                           &arr, &n)) != SATF_OK)
    return s;
  d->track_slices = (int)slices;
  /* every size from the document before allocating */
  size_t points = 0;
  for (const cJSON *e = arr->child; e; e = e->next) {
    int len = cJSON_IsArray(e) ? cJSON_GetArraySize(e) : 0;
    points += len > 1 ? (size_t)(len - 1) / 2 : 0;
  }
  if (points > SATF_SCENE_MAX_TRACK_POINTS)
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "tracks: %zu points, over the limit of %d", points,
                      SATF_SCENE_MAX_TRACK_POINTS);
  d->n_tracks = n;
  d->track_first = malloc((size_t)n * sizeof(int));
  d->track_count = malloc((size_t)n * sizeof(int));
  d->track_xy = malloc((2 * points + 1) * sizeof(float));
  if (!d->track_first || !d->track_count || !d->track_xy)
    return scene_nomem(ctx);
  size_t previous = scene_push_key(ctx, "tracks"), at = 0;
  int k = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, k++) {
    size_t item = scene_push_index(ctx, k);
    s = parse_track(ctx, e, d->track_slices, &d->track_first[k],
                    &d->track_count[k], d->track_xy + 2 * at);
    if (s == SATF_OK)
      at += (size_t)d->track_count[k];
    scene_pop(ctx, item);
  }
  scene_pop(ctx, previous);
  if (s == SATF_OK)
    s = parse_ends(ctx, obj, d);
  return s == SATF_OK ? parse_widths(ctx, obj, d) : s;
}

static satf_status parse_density(scene_ctx *ctx, const cJSON *cluster,
                                 const char *base_dir, satf_scene_density *d) {
  static const char *const types[] = {"procedural", "vdb", "tracks"};
  static const char *const vdb_keys[] = {"type", "file", "grid", NULL};
  static const cJSON empty = {0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, cluster, "density", 0, &obj);
  if (s != SATF_OK)
    return s;
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "density");
  int type;
  s = scene_key_enum(ctx, obj, "type", types, 3, SATF_SCENE_DENSITY_PROCEDURAL,
                     &type);
  d->type = (satf_scene_density_type)type;
  /* Procedural defaults stay meaningful for a VDB density too. */
  if (s == SATF_OK)
    s = parse_procedural(ctx, &empty, d);
  if (s == SATF_OK && d->type == SATF_SCENE_DENSITY_PROCEDURAL)
    s = parse_procedural(ctx, obj, d);
  if (s == SATF_OK && d->type == SATF_SCENE_DENSITY_TRACKS)
    s = parse_tracks(ctx, obj, d);
  if (s == SATF_OK && d->type == SATF_SCENE_DENSITY_VDB) {
    if ((s = scene_check_keys(ctx, obj, vdb_keys)) == SATF_OK &&
        (s = scene_key_path(ctx, obj, "file", 1, base_dir, &d->vdb_file)) ==
            SATF_OK) {
      s = scene_key_copy(ctx, obj, "grid", 0, &d->vdb_grid);
      if (s == SATF_OK && !d->vdb_grid) {
        d->vdb_grid = scene_copy_string("density");
        if (!d->vdb_grid)
          s = scene_nomem(ctx);
      }
    }
  }
  scene_pop(ctx, previous);
  return s;
}

/* The cluster geometry takes A, B and theta on one shared control polygon
 * (one parameter per control point), so their counts must agree; a
 * constant can be repeated to any count. */
static satf_status check_curve_counts(scene_ctx *ctx,
                                      const satf_scene_cluster *c) {
  const satf_scene_curve *curves[3] = {&c->a, &c->b, &c->twist};
  static const char *const names[3] = {"a", "b", "twist"};
  int first = -1;
  for (int i = 0; i < 3; i++) {
    if (curves[i]->count == 1)
      continue;
    if (first < 0) {
      first = i;
    } else if (curves[i]->count != curves[first]->count) {
      return scene_fail_key(ctx, names[i], SATF_ERR_ARGUMENT,
                            "has %d control values but %s has %d; a, b and "
                            "twist need the same count (or a single number)",
                            curves[i]->count, names[first],
                            curves[first]->count);
    }
  }
  return SATF_OK;
}

/* ---- prototype keys ---- */

static satf_status count_mismatch(scene_ctx *ctx, const char *key, int got,
                                  int want, const char *unit) {
  return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT,
                        "has %d %s but the static %s has %d; keys keep the "
                        "counts",
                        got, unit, key, want);
}

/* A key of the static cluster `user`: any of trajectory, a, b and twist,
 * with the static counts. */
static satf_status read_prototype_key(scene_ctx *ctx, const cJSON *e, void *out,
                                      const void *user) {
  static const char *const keys[] = {"frame", "trajectory", "a",
                                     "b",     "twist",      NULL};
  static const char *const fixed[] = {"shell", "density", NULL};
  const satf_scene_cluster *c = user;
  scene_proto_key *key = out;
  satf_status s;
  if ((s = scene_check_keys(ctx, e, keys)) != SATF_OK ||
      (s = scene_tracks_reject_fixed(ctx, e, fixed,
                                     "a prototype key may give trajectory, "
                                     "a, b and twist")) != SATF_OK)
    return s;
  if (cJSON_GetObjectItemCaseSensitive(e, "trajectory")) {
    satf_scene_cluster tmp = {0};
    s = parse_trajectory(ctx, e, &tmp);
    key->trajectory = tmp.trajectory; /* owned even on failure */
    if (s == SATF_OK && tmp.n_points != c->n_points)
      s = count_mismatch(ctx, "trajectory", tmp.n_points, c->n_points,
                         "control points");
    if (s != SATF_OK)
      return s;
  }
  static const char *const names[3] = {"a", "b", "twist"};
  const satf_scene_curve *statics[3] = {&c->a, &c->b, &c->twist};
  float **values[3] = {&key->a, &key->b, &key->twist};
  for (int i = 0; i < 3; i++) {
    if (!cJSON_GetObjectItemCaseSensitive(e, names[i]))
      continue;
    satf_scene_curve tmp = {0};
    s = parse_cluster_curve(ctx, e, names[i], &tmp);
    *values[i] = tmp.values;
    if (s == SATF_OK && tmp.count != statics[i]->count)
      s = count_mismatch(ctx, names[i], tmp.count, statics[i]->count,
                         "control values");
    if (s != SATF_OK)
      return s;
  }
  return SATF_OK;
}

/* The keys of macro_clusters[index].prototype (obj), the static cluster c
 * already parsed; the ctx path is the prototype's. */
static satf_status parse_prototype_keys(scene_ctx *ctx, const cJSON *obj,
                                        int index,
                                        const satf_scene_cluster *c) {
  scene_track scratch = {0}, *t = &scratch;
  if (scene_tracks_has_keys(ctx, obj)) {
    t = scene_anim_proto_tracks(ctx->scene->animation,
                                ctx->scene->n_macro_clusters);
    if (!t)
      return scene_nomem(ctx);
    t += index;
  }
  return scene_tracks_read(ctx, obj, sizeof(scene_proto_key),
                           read_prototype_key, c, t);
}

static satf_status parse_cluster(scene_ctx *ctx, const cJSON *obj,
                                 const char *base_dir, int index,
                                 satf_scene_cluster *c) {
  static const char *const keys[] = {"trajectory", "a",       "b",    "twist",
                                     "shell",      "density", "keys", NULL};
  satf_status s;
  if ((s = scene_check_keys(ctx, obj, keys)) != SATF_OK ||
      (s = parse_trajectory(ctx, obj, c)) != SATF_OK ||
      (s = parse_curve(ctx, obj, "a", &R_RADIUS, 1, 0, &c->a)) != SATF_OK)
    return s;
  if (cJSON_GetObjectItemCaseSensitive(obj, "b"))
    s = parse_curve(ctx, obj, "b", &R_RADIUS, 1, 0, &c->b);
  else
    s = copy_curve(ctx, &c->a, &c->b);
  if (s == SATF_OK &&
      (s = parse_curve(ctx, obj, "twist", &R_TWIST, 0, 0.0, &c->twist)) ==
          SATF_OK &&
      (s = check_curve_counts(ctx, c)) == SATF_OK &&
      (s = parse_shell(ctx, obj, &c->shell)) == SATF_OK &&
      (s = parse_density(ctx, obj, base_dir, &c->density)) == SATF_OK)
    s = parse_prototype_keys(ctx, obj, index, c);
  return s;
}

/* ---- macro-clusters (SATF sec. 3.1) ---- */

static satf_status parse_macro_cluster(scene_ctx *ctx, const cJSON *obj,
                                       const char *base_dir, int index,
                                       uint64_t *total_clusters,
                                       uint64_t *total_hsv,
                                       satf_scene_macro_cluster *mc) {
  static const char *const keys[] = {"name", "prototype", "instances", NULL};
  if (!cJSON_IsObject(obj))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(obj));
  const cJSON *proto, *instances;
  int n;
  satf_status s;
  if ((s = scene_check_keys(ctx, obj, keys)) != SATF_OK ||
      (s = scene_key_copy(ctx, obj, "name", 0, &mc->name)) != SATF_OK ||
      (s = scene_key_object(ctx, obj, "prototype", 1, &proto)) != SATF_OK)
    return s;
  size_t previous = scene_push_key(ctx, "prototype");
  s = parse_cluster(ctx, proto, base_dir, index, &mc->prototype);
  scene_pop(ctx, previous);
  if (s != SATF_OK || (s = scene_key_array(ctx, obj, "instances", 0, 1,
                                           SATF_SCENE_MAX_INSTANCES, &instances,
                                           &n)) != SATF_OK)
    return s;
  if (!instances)
    n = 1;
  /* Check the totals before allocating, so an absurd file costs nothing. */
  *total_clusters += (uint64_t)n;
  *total_hsv += (uint64_t)n * satf_scene_cluster_hsv_count(&mc->prototype);
  if (*total_clusters > SATF_SCENE_MAX_CLUSTERS)
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "brings the scene to %llu clusters, over the limit of "
                      "%d",
                      (unsigned long long)*total_clusters,
                      SATF_SCENE_MAX_CLUSTERS);
  if (*total_hsv > SATF_SCENE_MAX_HSV)
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "brings the scene's total HSV count (layers x st x su "
                      "over all instances) to %llu, over the limit of %llu",
                      (unsigned long long)*total_hsv, SATF_SCENE_MAX_HSV);
  mc->instances = malloc((size_t)n * sizeof *mc->instances);
  if (!mc->instances)
    return scene_nomem(ctx);
  mc->n_instances = n;
  if (!instances) {
    scene_matrix_identity(mc->instances[0].m);
    return SATF_OK;
  }
  previous = scene_push_key(ctx, "instances");
  int i = 0;
  for (const cJSON *e = instances->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    s = scene_parse_instance(ctx, e, index, i, &mc->instances[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_parse_macro_clusters(scene_ctx *ctx, const cJSON *root,
                                       const char *base_dir) {
  satf_scene *scene = ctx->scene;
  const cJSON *arr;
  int n;
  satf_status s = scene_key_array(ctx, root, "macro_clusters", 1, 1,
                                  SATF_SCENE_MAX_MACRO_CLUSTERS, &arr, &n);
  if (s != SATF_OK)
    return s;
  scene->macro_clusters = calloc((size_t)n, sizeof *scene->macro_clusters);
  if (!scene->macro_clusters)
    return scene_nomem(ctx);
  scene->n_macro_clusters = n;
  uint64_t total_clusters = 0, total_hsv = 0;
  size_t previous = scene_push_key(ctx, "macro_clusters");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    s = parse_macro_cluster(ctx, e, base_dir, i, &total_clusters, &total_hsv,
                            &scene->macro_clusters[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}
