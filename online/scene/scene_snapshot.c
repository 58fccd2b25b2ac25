/* scene_snapshot.c - snapshots of an animated scene (satf_scene_at_frame):
 * a deep copy of the static scene with every keyed value interpolated at
 * one frame, checked as the parser checks a static value. */
#include "satf/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_anim.h"
#include "scene_check.h"
#include "scene_fields.h"
#include "scene_interp.h"
#include "scene_report.h"
#include "scene_transform.h"

/* Cubic interpolation can overshoot between keys; values are clamped back
 * into what the parser accepts. A radius keeps a tiny positive floor. */
#define MIN_RADIUS 1e-6f
#define MAX_TWIST 1e4f

static int floats_equal(const float *a, const float *b, int n) {
  return n == 0 || memcmp(a, b, (size_t)n * sizeof *a) == 0;
}

/* ---- the static copy ---- */

static void *copy_bytes(const void *from, size_t size, int *failed) {
  if (!from)
    return NULL;
  void *to = malloc(size ? size : 1);
  if (!to) {
    *failed = 1;
    return NULL;
  }
  memcpy(to, from, size);
  return to;
}

static char *copy_string(const char *s, int *failed) {
  return s ? copy_bytes(s, strlen(s) + 1, failed) : NULL;
}

static void copy_curve(const satf_scene_curve *from, satf_scene_curve *to,
                       int *failed) {
  to->count = from->count;
  to->values = copy_bytes(from->values,
                          (size_t)from->count * sizeof *from->values, failed);
}

static void copy_macro_cluster(const satf_scene_macro_cluster *from,
                               satf_scene_macro_cluster *to, int *failed) {
  /* Every pointer is either the copy's own or NULL at any moment, so a
   * failure half way leaves something satf_scene_destroy can free. */
  const satf_scene_cluster *fc = &from->prototype;
  satf_scene_cluster *tc = &to->prototype;
  tc->shell = fc->shell;
  tc->density = fc->density;
  tc->density.vdb_file = copy_string(fc->density.vdb_file, failed);
  tc->density.vdb_grid = copy_string(fc->density.vdb_grid, failed);
  size_t nt = (size_t)fc->density.n_tracks,
         np = satf_scene_track_points(&fc->density);
  tc->density.track_first =
      copy_bytes(fc->density.track_first, nt * sizeof(int), failed);
  tc->density.track_count =
      copy_bytes(fc->density.track_count, nt * sizeof(int), failed);
  tc->density.track_xy =
      copy_bytes(fc->density.track_xy, 2 * np * sizeof(float), failed);
  tc->density.track_ends =
      copy_bytes(fc->density.track_ends, 6 * nt * sizeof(float), failed);
  tc->density.track_width =
      copy_bytes(fc->density.track_width, nt * sizeof(float), failed);
  tc->n_points = fc->n_points;
  tc->trajectory =
      copy_bytes(fc->trajectory,
                 (size_t)fc->n_points * 3 * sizeof *fc->trajectory, failed);
  copy_curve(&fc->a, &tc->a, failed);
  copy_curve(&fc->b, &tc->b, failed);
  copy_curve(&fc->twist, &tc->twist, failed);
  to->name = copy_string(from->name, failed);
  to->instances =
      copy_bytes(from->instances,
                 (size_t)from->n_instances * sizeof *from->instances, failed);
  to->n_instances = to->instances ? from->n_instances : 0;
}

static satf_scene *copy_static(const satf_scene *from) {
  satf_scene *to = calloc(1, sizeof *to);
  if (!to)
    return NULL;
  int failed = 0;
  to->material = from->material;
  to->effects = from->effects;
  to->camera = from->camera;
  to->image = from->image;
  memcpy(to->background, from->background, sizeof to->background);
  to->name = copy_string(from->name, &failed);
  to->description = copy_string(from->description, &failed);
  to->database = copy_string(from->database, &failed);
  to->strands_file = copy_string(from->strands_file, &failed);
  to->lights = copy_bytes(
      from->lights, (size_t)from->n_lights * sizeof *from->lights, &failed);
  to->n_lights = to->lights ? from->n_lights : 0;
  if (from->n_meshes > 0) {
    to->meshes = calloc((size_t)from->n_meshes, sizeof *to->meshes);
    if (to->meshes) {
      to->n_meshes = from->n_meshes;
      for (int i = 0; i < from->n_meshes; i++) {
        to->meshes[i] = from->meshes[i];
        to->meshes[i].file = copy_string(from->meshes[i].file, &failed);
      }
    } else {
      failed = 1;
    }
  }
  to->macro_clusters =
      calloc((size_t)from->n_macro_clusters, sizeof *to->macro_clusters);
  if (to->macro_clusters) {
    to->n_macro_clusters = from->n_macro_clusters;
    for (int i = 0; i < from->n_macro_clusters; i++)
      copy_macro_cluster(&from->macro_clusters[i], &to->macro_clusters[i],
                         &failed);
  } else if (from->n_macro_clusters > 0) {
    failed = 1;
  }
  if (failed) {
    satf_scene_destroy(to);
    return NULL;
  }
  return to;
}

/* ---- interpolation at one frame ---- */

static float clampf(float v, float lo, float hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

static void clamp_all(float *v, int n, float lo, float hi) {
  for (int i = 0; i < n; i++)
    v[i] = clampf(v[i], lo, hi);
}

/* Into the range the scene's table gives key (scene_fields.h). */
static void clamp_field(const scene_table *t, const char *key, float *v,
                        int n) {
  const scene_field *row = scene_field_find(t, key);
  clamp_all(v, n, (float)row->range.lo, (float)row->range.hi);
}

/* Blends one array-valued property: value(k) is key k's array. */
#define BLEND(w, value, count, out)                                            \
  do {                                                                         \
    const float *v_[4] = {value((w)->base), NULL, NULL, NULL};                 \
    for (int i_ = 0; i_ < (w)->n_terms; i_++)                                  \
      v_[1 + i_] = value((w)->key[i_]);                                        \
    scene_interp_blend((w), v_, (count), (out));                               \
  } while (0)

static satf_status prototype_at(scene_ctx *ctx, const scene_track *t,
                                const satf_scene_cluster *st, double frame,
                                satf_scene_cluster *out) {
  const scene_proto_key *keys = t->keys;
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
#define TRAJ(k) (keys[k].trajectory ? keys[k].trajectory : st->trajectory)
#define A(k) (keys[k].a ? keys[k].a : st->a.values)
#define B(k) (keys[k].b ? keys[k].b : st->b.values)
#define TWIST(k) (keys[k].twist ? keys[k].twist : st->twist.values)
  BLEND(&w, TRAJ, 3 * st->n_points, out->trajectory);
  BLEND(&w, A, st->a.count, out->a.values);
  BLEND(&w, B, st->b.count, out->b.values);
  BLEND(&w, TWIST, st->twist.count, out->twist.values);
#undef TRAJ
#undef A
#undef B
#undef TWIST
  clamp_all(out->trajectory, 3 * st->n_points, -SATF_SCENE_MAX_COORD,
            SATF_SCENE_MAX_COORD);
  clamp_all(out->a.values, st->a.count, MIN_RADIUS, SATF_SCENE_MAX_COORD);
  clamp_all(out->b.values, st->b.count, MIN_RADIUS, SATF_SCENE_MAX_COORD);
  clamp_all(out->twist.values, st->twist.count, -MAX_TWIST, MAX_TWIST);
  if (!(scene_trajectory_extent(out->trajectory, out->n_points) > 1e-6))
    return scene_fail_key(ctx, "trajectory", SATF_ERR_ARGUMENT,
                          "all %d control points coincide", out->n_points);
  return SATF_OK;
}

static int same_matrices(const scene_xform_key *keys, const scene_weights *w) {
  for (int i = 0; i < w->n_terms; i++)
    if (!floats_equal(keys[w->key[i]].form.m, keys[w->base].form.m, 16))
      return 0;
  return 1;
}

/* Translation and stretch follow the cubic, the rotation a slerp between
 * the two keys around the frame: M = T R S. */
static satf_status instance_at(scene_ctx *ctx, const scene_track *t,
                               double frame, float m[16]) {
  const scene_xform_key *keys = t->keys;
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
  if (same_matrices(keys, &w)) {
    memcpy(m, keys[w.base].form.m, 16 * sizeof *m);
    return SATF_OK;
  }
  float translate[3], stretch[9];
#define TRANSLATE(k) (keys[k].translate)
#define STRETCH(k) (keys[k].stretch)
  BLEND(&w, TRANSLATE, 3, translate);
  BLEND(&w, STRETCH, 9, stretch);
#undef TRANSLATE
#undef STRETCH
  double q[4], r[9];
  scene_quat_slerp(keys[w.base].rotation, keys[w.next].rotation, w.u, q);
  scene_quat_to_matrix(q, r);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++)
      m[4 * i + j] =
          (float)(r[3 * i] * stretch[j] + r[3 * i + 1] * stretch[3 + j] +
                  r[3 * i + 2] * stretch[6 + j]);
    m[4 * i + 3] =
        clampf(translate[i], -SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD);
  }
  m[12] = m[13] = m[14] = 0.0f;
  m[15] = 1.0f;
  double det = scene_matrix_det3(m);
  if (!(fabs(det) >= 1e-12) || !isfinite(det))
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "the interpolated transform is singular (determinant "
                      "%g)",
                      det);
  return SATF_OK;
}

static satf_status camera_at(scene_ctx *ctx, const scene_track *t,
                             int sets_position, double frame,
                             satf_scene_camera *cam) {
  const scene_camera_key *keys = t->keys;
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
#define POSITION(k) (keys[k].position)
#define TARGET(k) (keys[k].target)
#define UP(k) (keys[k].up)
#define FOV(k) (&keys[k].fov_y)
  BLEND(&w, POSITION, 3, cam->position);
  BLEND(&w, TARGET, 3, cam->target);
  BLEND(&w, UP, 3, cam->up);
  BLEND(&w, FOV, 1, &cam->fov_y);
#undef POSITION
#undef TARGET
#undef FOV
  clamp_field(&SCENE_CAMERA, "position", cam->position, 3);
  clamp_field(&SCENE_CAMERA, "target", cam->target, 3);
  clamp_field(&SCENE_CAMERA, "fov_y", &cam->fov_y, 1);
  if (sets_position)
    cam->automatic = 0;
  float up[3];
  memcpy(up, cam->up, sizeof up);
  satf_status s = scene_check_camera_view(ctx, cam);
  /* A key's up is normalized already: keep it bit for bit. */
  if (s == SATF_OK && floats_equal(up, UP(w.base), 3))
    memcpy(cam->up, up, sizeof up);
#undef UP
  return s;
}

static satf_status light_at(scene_ctx *ctx, const scene_track *t, double frame,
                            satf_scene_light *light) {
  const scene_light_key *keys = t->keys;
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
  float vector[3];
#define VECTOR(k) (keys[k].vector)
#define COLOR(k) (keys[k].color)
#define INTENSITY(k) (&keys[k].intensity)
  BLEND(&w, VECTOR, 3, vector);
  BLEND(&w, COLOR, 3, light->color);
  BLEND(&w, INTENSITY, 1, &light->intensity);
#undef COLOR
#undef INTENSITY
  clamp_field(&SCENE_LIGHT,
              light->type == SATF_SCENE_LIGHT_POINT ? "position" : "direction",
              vector, 3);
  clamp_field(&SCENE_LIGHT, "color", light->color, 3);
  clamp_field(&SCENE_LIGHT, "intensity", &light->intensity, 1);
  if (light->type == SATF_SCENE_LIGHT_POINT) {
    memcpy(light->position, vector, sizeof vector);
    return SATF_OK;
  }
  double len;
  satf_status s = scene_check_direction(ctx, vector, &len);
  if (s != SATF_OK)
    return s;
  memcpy(light->direction, vector, sizeof vector);
  if (!floats_equal(vector, VECTOR(w.base), 3)) /* else a normalized key */
    scene_normalize(light->direction, len);
#undef VECTOR
  return SATF_OK;
}

static satf_status animate(scene_ctx *ctx, const satf_scene *scene,
                           double frame, satf_scene *snap) {
  const satf_scene_animation *anim = scene->animation;
  satf_status s = SATF_OK;
  for (int i = 0; i < anim->n_protos && s == SATF_OK; i++) {
    if (anim->protos[i].n_keys == 0)
      continue;
    size_t previous = scene_push_key(ctx, "macro_clusters");
    scene_push_index(ctx, i);
    scene_push_key(ctx, "prototype");
    s = prototype_at(ctx, &anim->protos[i], &scene->macro_clusters[i].prototype,
                     frame, &snap->macro_clusters[i].prototype);
    scene_pop(ctx, previous);
  }
  for (int i = 0; i < anim->n_instance_tracks && s == SATF_OK; i++) {
    const scene_instance_track *it = &anim->instances[i];
    if (it->track.n_keys == 0)
      continue;
    size_t previous = scene_push_key(ctx, "macro_clusters");
    scene_push_index(ctx, it->macro_cluster);
    scene_push_key(ctx, "instances");
    scene_push_index(ctx, it->instance);
    s = instance_at(
        ctx, &it->track, frame,
        snap->macro_clusters[it->macro_cluster].instances[it->instance].m);
    scene_pop(ctx, previous);
  }
  if (s == SATF_OK && anim->camera.n_keys > 0) {
    size_t previous = scene_push_key(ctx, "camera");
    s = camera_at(ctx, &anim->camera, anim->camera_sets_position, frame,
                  &snap->camera);
    scene_pop(ctx, previous);
  }
  for (int i = 0; i < anim->n_lights && s == SATF_OK; i++) {
    if (anim->lights[i].n_keys == 0)
      continue;
    size_t previous = scene_push_key(ctx, "lights");
    scene_push_index(ctx, i);
    s = light_at(ctx, &anim->lights[i], frame, &snap->lights[i]);
    scene_pop(ctx, previous);
  }
  return s;
}

satf_status satf_scene_at_frame(const satf_scene *scene, double frame,
                                satf_scene **out, satf_error *err) {
  if (!out)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_at_frame: no output scene");
  *out = NULL;
  if (!scene)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_at_frame: no scene");
  if (!isfinite(frame))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: frame %g is not a finite number", scene->name,
                          frame);
  satf_scene *snap = copy_static(scene);
  if (!snap)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                          scene->name);
  if (scene->animation) {
    /* Messages read "NAME at frame F: key.path: what is wrong". */
    char name[600];
    snprintf(name, sizeof name, "%s at frame %g", scene->name, frame);
    scene_ctx ctx = {.name = name, .err = err, .scene = snap};
    satf_status s = animate(&ctx, scene, frame, snap);
    if (s != SATF_OK) {
      satf_scene_destroy(snap);
      return s;
    }
  }
  *out = snap;
  return SATF_OK;
}
