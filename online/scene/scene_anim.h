/* scene_anim.h - the keyframes of an animated scene (samples/README.md,
 * "Animation"): struct satf_scene_animation, the per-object key tracks hung
 * off a satf_scene, and their lifetime. Plain data: reading them from JSON
 * is scene_tracks.h and the parsers, interpolating them scene_interp.h and
 * scene_snapshot.c, writing them scene_write.c. */
#ifndef SATF_ONLINE_SCENE_ANIM_H
#define SATF_ONLINE_SCENE_ANIM_H

#include "satf/scene.h"

/* Keys of one animated object: frames strictly increasing, keys an array of
 * n_keys structs of the object's key type (below). */
typedef struct scene_track {
  int n_keys; /* 0: the object does not move */
  double *frames;
  void *keys;
} scene_track;

/* A prototype's geometry at one key; a NULL array is the static one (the
 * key did not give it). */
typedef struct scene_proto_key {
  float *trajectory; /* 3 * n_points */
  float *a, *b, *twist;
} scene_proto_key;

/* A transform as written: a matrix, or translate / rotate (axis as written,
 * angle in degrees) / scale. m is composed from it. */
typedef struct scene_xform {
  int is_matrix;
  float m[16];
  float translate[3];
  float axis[3];
  double degrees;
  float scale[3];
} scene_xform;

/* An instance transform at one key: as written, and split for
 * interpolation into m = T(translate) R(rotation) S(stretch). */
typedef struct scene_xform_key {
  scene_xform form;
  float translate[3];
  float stretch[9];   /* symmetric for a matrix key, diag(scale) for TRS */
  double rotation[4]; /* unit quaternion (w, x, y, z) */
} scene_xform_key;

typedef struct scene_instance_track {
  int macro_cluster, instance;
  scene_xform base;  /* the static transform as written */
  scene_track track; /* of scene_xform_key */
} scene_instance_track;

/* What a camera or light key gave; the rest is the static value. */
enum {
  SCENE_GIVES_POSITION = 1,
  SCENE_GIVES_TARGET = 2,
  SCENE_GIVES_UP = 4,
  SCENE_GIVES_FOV = 8,
  SCENE_GIVES_VECTOR = 16,
  SCENE_GIVES_COLOR = 32,
  SCENE_GIVES_INTENSITY = 64
};

typedef struct scene_camera_key {
  float position[3], target[3], up[3];
  float fov_y;
  unsigned given;
} scene_camera_key;

typedef struct scene_light_key {
  float vector[3]; /* direction or position, by the light's type */
  float color[3];
  float intensity;
  unsigned given;
} scene_light_key;

struct satf_scene_animation {
  double fps;
  int first, last;     /* frame range, first <= last */
  long total_keys;     /* over the scene, against SATF_SCENE_MAX_KEYS_TOTAL */
  int n_protos;        /* = n_macro_clusters once a prototype has keys */
  scene_track *protos; /* of scene_proto_key */
  int n_instance_tracks, instance_capacity;
  scene_instance_track *instances; /* in file order */
  scene_track camera;              /* of scene_camera_key */
  int camera_sets_position; /* some key gives "position": not automatic */
  int n_lights;             /* = scene n_lights once a light has keys */
  scene_track *lights;      /* of scene_light_key */
};

satf_scene_animation *scene_anim_create(double fps, int first, int last);
void scene_anim_destroy(satf_scene_animation *anim);

/* anim->protos (or lights) for n objects, allocated on first use; NULL
 * when out of memory. */
scene_track *scene_anim_proto_tracks(satf_scene_animation *anim, int n);
scene_track *scene_anim_light_tracks(satf_scene_animation *anim, int n);

/* A new, zeroed instance track; NULL when out of memory. */
scene_instance_track *scene_anim_add_instance(satf_scene_animation *anim,
                                              int macro_cluster, int instance);

/* Allocates n zeroed keys of key_size bytes and their frames into t;
 * returns 0 when out of memory. */
int scene_track_alloc(scene_track *t, int n, size_t key_size);

#endif
