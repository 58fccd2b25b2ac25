/* scene_anim.h - the keyframes of an animated scene (samples/README.md,
 * "Animation"): owns struct satf_scene_animation, the per-object key tracks
 * hung off a satf_scene, and the parsers that fill them. Interpolation
 * itself is scene_interp.h; snapshots are scene_anim.c. */
#ifndef SATF_ONLINE_SCENE_ANIM_H
#define SATF_ONLINE_SCENE_ANIM_H

#include <cjson/cJSON.h>

#include "scene_json.h"
#include "satf/scene.h"

/* A prototype's geometry at one key; a NULL array is the static one. */
typedef struct scene_proto_key {
  float *trajectory; /* 3 * n_points */
  float *a, *b, *twist;
} scene_proto_key;

typedef struct scene_proto_track {
  int n_keys; /* 0: the prototype does not move */
  double *frames;
  scene_proto_key *keys;
} scene_proto_track;

/* An instance transform at one key, both as the static parser composes it
 * (m, used as is on a key) and split for interpolation: m = T(translate)
 * R(rotation) S(stretch). */
typedef struct scene_xform_key {
  float m[16];
  float translate[3];
  float stretch[9];   /* symmetric for a matrix key, diag(scale) for TRS */
  double rotation[4]; /* unit quaternion (w, x, y, z) */
} scene_xform_key;

typedef struct scene_instance_track {
  int macro_cluster, instance;
  int n_keys;
  double *frames;
  scene_xform_key *keys;
} scene_instance_track;

typedef struct scene_camera_key {
  float position[3], target[3], up[3];
  float fov_y;
} scene_camera_key;

typedef struct scene_light_key {
  float vector[3]; /* direction or position, by the light's type */
  float color[3];
  float intensity;
} scene_light_key;

typedef struct scene_camera_track {
  int n_keys;
  int sets_position; /* some key gives "position": no longer automatic */
  double *frames;
  scene_camera_key *keys;
} scene_camera_track;

typedef struct scene_light_track {
  int n_keys;
  double *frames;
  scene_light_key *keys;
} scene_light_track;

struct satf_scene_animation {
  double fps;
  int first, last; /* frame range, first <= last */
  long total_keys; /* over the scene, against SATF_SCENE_MAX_KEYS_TOTAL */
  int n_protos;    /* = n_macro_clusters once a prototype has keys */
  scene_proto_track *protos;
  int n_instance_tracks, instance_capacity;
  scene_instance_track *instances; /* in file order */
  scene_camera_track camera;
  int n_lights; /* = scene n_lights once a light has keys */
  scene_light_track *lights;
};

void scene_anim_destroy(satf_scene_animation *anim);

/* root.animation into ctx->scene->animation (left NULL when absent). */
satf_status scene_anim_parse_settings(scene_ctx *ctx, const cJSON *root);

/* obj.keys: absent gives *count 0; present it needs the animation object,
 * must be an array of 1..SATF_SCENE_MAX_KEYS and is counted against the
 * scene-wide key limit. */
satf_status scene_anim_keys_array(scene_ctx *ctx, const cJSON *obj,
                                  const cJSON **arr, int *count);

/* keys[index].frame (key is that entry; the path already ends in
 * "keys[index]"): an object with a number in the frame range, after
 * previous (index > 0). */
satf_status scene_anim_key_frame(scene_ctx *ctx, const cJSON *key, int index,
                                 double previous, double *frame);

/* Fails with "KEY: cannot be animated; ..." for each of obj's keys listed in
 * fixed (the static-only keys of that object). */
satf_status scene_anim_reject_fixed(scene_ctx *ctx, const cJSON *obj,
                                    const char *const *fixed, const char *what);

/* The keys of macro_clusters[index].prototype (obj), the static cluster c
 * already parsed; the ctx path is the prototype's. */
satf_status scene_anim_parse_prototype_keys(scene_ctx *ctx, const cJSON *obj,
                                            int index,
                                            const satf_scene_cluster *c);

/* A new, zeroed instance track of n keys, frames and keys allocated. */
satf_status scene_anim_add_instance_track(scene_ctx *ctx, int macro_cluster,
                                          int instance, int n,
                                          scene_instance_track **out);

/* The keys of the camera (obj, the ctx path is "camera"). */
satf_status scene_anim_parse_camera_keys(scene_ctx *ctx, const cJSON *obj,
                                         const satf_scene_camera *cam);

/* The keys of lights[index] (obj; the ctx path is the light's). */
satf_status scene_anim_parse_light_keys(scene_ctx *ctx, const cJSON *obj,
                                        int index,
                                        const satf_scene_light *light);

#endif
