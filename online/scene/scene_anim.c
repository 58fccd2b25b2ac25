/* scene_anim.c - the keyframes' lifetime, the public queries about them
 * (satf_scene_is_animated and friends) and the constructors that let a
 * program animate a scene it builds (satf_scene_set_animation,
 * satf_scene_add_prototype_key). */
#include "scene_anim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

satf_scene_animation *scene_anim_create(double fps, int first, int last) {
  satf_scene_animation *anim = calloc(1, sizeof *anim);
  if (anim) {
    anim->fps = fps;
    anim->first = first;
    anim->last = last;
  }
  return anim;
}

static void free_track(scene_track *t) {
  free(t->frames);
  free(t->keys);
}

void scene_anim_destroy(satf_scene_animation *anim) {
  if (!anim)
    return;
  for (int i = 0; i < anim->n_protos; i++) {
    scene_proto_key *keys = anim->protos[i].keys;
    for (int k = 0; k < anim->protos[i].n_keys; k++) {
      free(keys[k].trajectory);
      free(keys[k].a);
      free(keys[k].b);
      free(keys[k].twist);
    }
    free_track(&anim->protos[i]);
  }
  free(anim->protos);
  for (int i = 0; i < anim->n_instance_tracks; i++)
    free_track(&anim->instances[i].track);
  free(anim->instances);
  free_track(&anim->camera);
  for (int i = 0; i < anim->n_lights; i++)
    free_track(&anim->lights[i]);
  free(anim->lights);
  free(anim);
}

int scene_track_alloc(scene_track *t, int n, size_t key_size) {
  t->frames = calloc((size_t)n, sizeof *t->frames);
  t->keys = calloc((size_t)n, key_size);
  if (!t->frames || !t->keys)
    return 0;
  t->n_keys = n;
  return 1;
}

scene_track *scene_anim_proto_tracks(satf_scene_animation *anim, int n) {
  if (!anim->protos) {
    anim->protos = calloc((size_t)n, sizeof *anim->protos);
    if (!anim->protos)
      return NULL;
    anim->n_protos = n;
  }
  return anim->protos;
}

scene_track *scene_anim_light_tracks(satf_scene_animation *anim, int n) {
  if (!anim->lights) {
    anim->lights = calloc((size_t)n, sizeof *anim->lights);
    if (!anim->lights)
      return NULL;
    anim->n_lights = n;
  }
  return anim->lights;
}

scene_instance_track *scene_anim_add_instance(satf_scene_animation *anim,
                                              int macro_cluster, int instance) {
  if (anim->n_instance_tracks == anim->instance_capacity) {
    int cap = anim->instance_capacity ? 2 * anim->instance_capacity : 16;
    scene_instance_track *grown =
        realloc(anim->instances, (size_t)cap * sizeof *grown);
    if (!grown)
      return NULL;
    anim->instances = grown;
    anim->instance_capacity = cap;
  }
  scene_instance_track *t = &anim->instances[anim->n_instance_tracks++];
  memset(t, 0, sizeof *t);
  t->macro_cluster = macro_cluster;
  t->instance = instance;
  return t;
}

/* ---- public queries ---- */

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

/* ---- constructors ---- */

satf_status satf_scene_set_animation(satf_scene *scene, double fps, int first,
                                     int last, satf_error *err) {
  const char *name = scene && scene->name ? scene->name : "<scene>";
  if (!scene || scene->animation)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: no scene, or one already animated", name);
  if (!(fps > 0.0 && fps <= SATF_SCENE_MAX_FPS) || first > last ||
      first < -SATF_SCENE_MAX_FRAME || last > SATF_SCENE_MAX_FRAME)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: animation: fps %g or frames [%d, %d] out of "
                          "range",
                          name, fps, first, last);
  scene->animation = scene_anim_create(fps, first, last);
  return scene->animation
             ? SATF_OK
             : satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
}

static float *copy_floats(const float *v, int n, int *failed) {
  if (!v)
    return NULL;
  float *c = malloc((size_t)n * sizeof *c);
  if (!c) {
    *failed = 1;
    return NULL;
  }
  memcpy(c, v, (size_t)n * sizeof *c);
  return c;
}

static int grow_track(scene_track *t) {
  double *frames = realloc(t->frames, (size_t)(t->n_keys + 1) * sizeof *frames);
  if (frames)
    t->frames = frames;
  scene_proto_key *keys =
      realloc(t->keys, (size_t)(t->n_keys + 1) * sizeof *keys);
  if (keys)
    t->keys = keys;
  return frames && keys;
}

satf_status satf_scene_add_prototype_key(satf_scene *scene, int index,
                                         double frame, const float *trajectory,
                                         const float *a, const float *b,
                                         const float *twist, satf_error *err) {
  const char *name = scene && scene->name ? scene->name : "<scene>";
  satf_scene_animation *anim = scene ? scene->animation : NULL;
  if (!anim || index < 0 || index >= scene->n_macro_clusters)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: no animation or no macro-cluster %d", name,
                          index);
  scene_track *tracks = scene_anim_proto_tracks(anim, scene->n_macro_clusters);
  if (!tracks)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  scene_track *t = &tracks[index];
  if (!isfinite(frame) || frame < anim->first || frame > anim->last ||
      (t->n_keys > 0 && !(frame > t->frames[t->n_keys - 1])) ||
      t->n_keys >= SATF_SCENE_MAX_KEYS ||
      anim->total_keys >= SATF_SCENE_MAX_KEYS_TOTAL)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: macro_clusters[%d]: key at frame %g is out of "
                          "order, out of range or over the key limits",
                          name, index, frame);
  if (!grow_track(t))
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  const satf_scene_cluster *c = &scene->macro_clusters[index].prototype;
  int failed = 0;
  scene_proto_key key = {copy_floats(trajectory, 3 * c->n_points, &failed),
                         copy_floats(a, c->a.count, &failed),
                         copy_floats(b, c->b.count, &failed),
                         copy_floats(twist, c->twist.count, &failed)};
  t->frames[t->n_keys] = frame;
  ((scene_proto_key *)t->keys)[t->n_keys++] = key; /* freed with the scene */
  anim->total_keys++;
  return failed ? satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name)
                : SATF_OK;
}
