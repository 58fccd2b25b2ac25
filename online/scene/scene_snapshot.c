/* scene_anim.c - snapshots of an animated scene (satf/anim.h): a deep copy
 * of the static scene with every keyed value interpolated at one frame,
 * the comparisons that tell a renderer what moved, and the lifetime of the
 * keyframes. */
#include "satf/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_anim.h"
#include "scene_interp.h"
#include "scene_json.h"
#include "scene_parse.h"
#include "scene_transform.h"

/* Cubic interpolation can overshoot between keys; values are clamped back
 * into what the parser accepts. A radius keeps a tiny positive floor. */
#define MIN_RADIUS 1e-6f
#define MAX_TWIST 1e4f

void scene_anim_destroy(satf_scene_animation *anim) {
  if (!anim)
    return;
  for (int i = 0; i < anim->n_protos; i++) {
    scene_proto_track *t = &anim->protos[i];
    for (int k = 0; k < t->n_keys; k++) {
      free(t->keys[k].trajectory);
      free(t->keys[k].a);
      free(t->keys[k].b);
      free(t->keys[k].twist);
    }
    free(t->frames);
    free(t->keys);
  }
  free(anim->protos);
  for (int i = 0; i < anim->n_instance_tracks; i++) {
    free(anim->instances[i].frames);
    free(anim->instances[i].keys);
  }
  free(anim->instances);
  free(anim->camera.frames);
  free(anim->camera.keys);
  for (int i = 0; i < anim->n_lights; i++) {
    free(anim->lights[i].frames);
    free(anim->lights[i].keys);
  }
  free(anim->lights);
  free(anim);
}

int satf_scene_is_animated(const satf_scene *scene) {
  return scene && scene->animation;
}

int satf_scene_frame_range(const satf_scene *scene, int *first, int *last) {
  int animated = satf_scene_is_animated(scene);
  if (first)
    *first = animated ? scene->animation->first : 0;
  if (last)
    *last = animated ? scene->animation->last : 0;
  return animated;
}

double satf_scene_fps(const satf_scene *scene) {
  return satf_scene_is_animated(scene) ? scene->animation->fps : 0.0;
}

int satf_scene_prototype_is_animated(const satf_scene *scene, int index) {
  if (!satf_scene_is_animated(scene) || index < 0 ||
      index >= scene->animation->n_protos)
    return 0;
  return scene->animation->protos[index].n_keys > 0;
}

int satf_scene_instance_is_animated(const satf_scene *scene, int index,
                                    int instance) {
  if (!satf_scene_is_animated(scene))
    return 0;
  const satf_scene_animation *anim = scene->animation;
  for (int i = 0; i < anim->n_instance_tracks; i++)
    if (anim->instances[i].macro_cluster == index &&
        anim->instances[i].instance == instance)
      return 1;
  return 0;
}

/* ---- equality ---- */

static int floats_equal(const float *a, const float *b, int n) {
  return n == 0 || memcmp(a, b, (size_t)n * sizeof *a) == 0;
}

static int curves_equal(const satf_scene_curve *a, const satf_scene_curve *b) {
  return a->count == b->count && floats_equal(a->values, b->values, a->count);
}

static int strings_equal(const char *a, const char *b) {
  return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

static int densities_equal(const satf_scene_density *a,
                           const satf_scene_density *b) {
  return a->type == b->type && a->strands == b->strands && a->seed == b->seed &&
         a->layout == b->layout &&
         floats_equal(&a->strand_width, &b->strand_width, 1) &&
         floats_equal(&a->scale, &b->scale, 1) && a->clumps == b->clumps &&
         floats_equal(&a->clump_spread, &b->clump_spread, 1) &&
         a->holes == b->holes &&
         floats_equal(&a->hole_radius, &b->hole_radius, 1) &&
         floats_equal(&a->gradient, &b->gradient, 1) &&
         strings_equal(a->vdb_file, b->vdb_file) &&
         strings_equal(a->vdb_grid, b->vdb_grid);
}

int satf_scene_prototype_equal(const satf_scene_cluster *a,
                               const satf_scene_cluster *b) {
  return a->n_points == b->n_points &&
         floats_equal(a->trajectory, b->trajectory, 3 * a->n_points) &&
         curves_equal(&a->a, &b->a) && curves_equal(&a->b, &b->b) &&
         curves_equal(&a->twist, &b->twist) &&
         a->shell.layers == b->shell.layers && a->shell.st == b->shell.st &&
         a->shell.su == b->shell.su &&
         floats_equal(&a->shell.core, &b->shell.core, 1) &&
         densities_equal(&a->density, &b->density);
}

int satf_scene_instances_equal(const satf_scene_macro_cluster *a,
                               const satf_scene_macro_cluster *b) {
  if (a->n_instances != b->n_instances)
    return 0;
  for (int j = 0; j < a->n_instances; j++)
    if (!floats_equal(a->instances[j].m, b->instances[j].m, 16))
      return 0;
  return 1;
}

int satf_scene_camera_equal(const satf_scene_camera *a,
                            const satf_scene_camera *b) {
  return floats_equal(a->position, b->position, 3) &&
         floats_equal(a->target, b->target, 3) &&
         floats_equal(a->up, b->up, 3) &&
         floats_equal(&a->fov_y, &b->fov_y, 1) &&
         floats_equal(&a->near_clip, &b->near_clip, 1) &&
         floats_equal(&a->far_clip, &b->far_clip, 1) &&
         a->automatic == b->automatic;
}

int satf_scene_light_equal(const satf_scene_light *a,
                           const satf_scene_light *b) {
  return a->type == b->type && floats_equal(a->direction, b->direction, 3) &&
         floats_equal(a->position, b->position, 3) &&
         floats_equal(a->color, b->color, 3) &&
         floats_equal(&a->intensity, &b->intensity, 1);
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

/* Blends one array-valued property: value(k) is key k's array. */
#define BLEND(w, value, count, out)                                            \
  do {                                                                         \
    const float *v_[4] = {value((w)->base), NULL, NULL, NULL};                 \
    for (int i_ = 0; i_ < (w)->n_terms; i_++)                                  \
      v_[1 + i_] = value((w)->key[i_]);                                        \
    scene_interp_blend((w), v_, (count), (out));                               \
  } while (0)

static satf_status prototype_at(scene_ctx *ctx, const scene_proto_track *t,
                                const satf_scene_cluster *st, double frame,
                                satf_scene_cluster *out) {
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
#define TRAJ(k) (t->keys[k].trajectory ? t->keys[k].trajectory : st->trajectory)
#define A(k) (t->keys[k].a ? t->keys[k].a : st->a.values)
#define B(k) (t->keys[k].b ? t->keys[k].b : st->b.values)
#define TWIST(k) (t->keys[k].twist ? t->keys[k].twist : st->twist.values)
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
  double extent = 0.0;
  for (int p = 1; p < out->n_points; p++) {
    float d[3];
    for (int k = 0; k < 3; k++)
      d[k] = out->trajectory[3 * p + k] - out->trajectory[k];
    double len = scene_vec_length(d);
    if (len > extent)
      extent = len;
  }
  if (!(extent > 1e-6))
    return scene_fail_key(ctx, "trajectory", SATF_ERR_ARGUMENT,
                          "all %d control points coincide", out->n_points);
  return SATF_OK;
}

static int same_matrices(const scene_instance_track *t,
                         const scene_weights *w) {
  for (int i = 0; i < w->n_terms; i++)
    if (!floats_equal(t->keys[w->key[i]].m, t->keys[w->base].m, 16))
      return 0;
  return 1;
}

/* Translation and stretch follow the cubic, the rotation a slerp between
 * the two keys around the frame: M = T R S. */
static satf_status instance_at(scene_ctx *ctx, const scene_instance_track *t,
                               double frame, float m[16]) {
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
  if (same_matrices(t, &w)) {
    memcpy(m, t->keys[w.base].m, 16 * sizeof *m);
    return SATF_OK;
  }
  float translate[3], stretch[9];
#define TRANSLATE(k) (t->keys[k].translate)
#define STRETCH(k) (t->keys[k].stretch)
  BLEND(&w, TRANSLATE, 3, translate);
  BLEND(&w, STRETCH, 9, stretch);
#undef TRANSLATE
#undef STRETCH
  double q[4], r[9];
  scene_quat_slerp(t->keys[w.base].rotation, t->keys[w.next].rotation, w.u, q);
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

static satf_status camera_at(scene_ctx *ctx, const scene_camera_track *t,
                             double frame, satf_scene_camera *cam) {
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
#define POSITION(k) (t->keys[k].position)
#define TARGET(k) (t->keys[k].target)
#define UP(k) (t->keys[k].up)
#define FOV(k) (&t->keys[k].fov_y)
  BLEND(&w, POSITION, 3, cam->position);
  BLEND(&w, TARGET, 3, cam->target);
  BLEND(&w, UP, 3, cam->up);
  BLEND(&w, FOV, 1, &cam->fov_y);
#undef POSITION
#undef TARGET
#undef FOV
  clamp_all(cam->position, 3, -SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD);
  clamp_all(cam->target, 3, -SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD);
  cam->fov_y = clampf(cam->fov_y, 0.1f, 179.0f);
  if (t->sets_position)
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

static satf_status light_at(scene_ctx *ctx, const scene_light_track *t,
                            double frame, satf_scene_light *light) {
  scene_weights w;
  scene_interp_weights(t->frames, t->n_keys, frame, &w);
  float vector[3];
#define VECTOR(k) (t->keys[k].vector)
#define COLOR(k) (t->keys[k].color)
#define INTENSITY(k) (&t->keys[k].intensity)
  BLEND(&w, VECTOR, 3, vector);
  BLEND(&w, COLOR, 3, light->color);
  BLEND(&w, INTENSITY, 1, &light->intensity);
#undef COLOR
#undef INTENSITY
  clamp_all(vector, 3, -SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD);
  clamp_all(light->color, 3, 0.0f, 1.0f);
  light->intensity = clampf(light->intensity, 0.0f, 1e6f);
  if (light->type == SATF_SCENE_LIGHT_POINT) {
    memcpy(light->position, vector, sizeof vector);
    return SATF_OK;
  }
  double len = scene_vec_length(vector);
  if (!(len > 1e-9))
    return scene_fail_key(ctx, "direction", SATF_ERR_ARGUMENT,
                          "has zero length");
  if (floats_equal(vector, VECTOR(w.base), 3)) {
    memcpy(light->direction, vector, sizeof vector); /* normalized key */
  } else {
    for (int k = 0; k < 3; k++)
      light->direction[k] = (float)(vector[k] / len);
  }
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
    const scene_instance_track *t = &anim->instances[i];
    size_t previous = scene_push_key(ctx, "macro_clusters");
    scene_push_index(ctx, t->macro_cluster);
    scene_push_key(ctx, "instances");
    scene_push_index(ctx, t->instance);
    s = instance_at(
        ctx, t, frame,
        snap->macro_clusters[t->macro_cluster].instances[t->instance].m);
    scene_pop(ctx, previous);
  }
  if (s == SATF_OK && anim->camera.n_keys > 0) {
    size_t previous = scene_push_key(ctx, "camera");
    s = camera_at(ctx, &anim->camera, frame, &snap->camera);
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
