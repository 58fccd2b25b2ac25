/* scene_anim_parse.c - the keyframe part of the scene schema
 * (samples/README.md, "Animation"): the root "animation" object and the
 * "keys" arrays of prototypes, the camera and lights (instances:
 * scene_instance.c). A key is the static object with the key's values put
 * over it, validated as the static object is. */
#include <stdlib.h>
#include <string.h>

#include "scene_anim.h"
#include "scene_parse.h"

satf_status scene_anim_parse_settings(scene_ctx *ctx, const cJSON *root) {
  static const char *const keys[] = {"fps", "frames", NULL};
  static const scene_range r_fps = {0, SATF_SCENE_MAX_FPS, 1, 0};
  static const scene_range r_frame = {-SATF_SCENE_MAX_FRAME,
                                      SATF_SCENE_MAX_FRAME, 0, 1};
  const cJSON *obj, *frames;
  int n;
  satf_status s = scene_key_object(ctx, root, "animation", 0, &obj);
  if (s != SATF_OK || !obj)
    return s;
  satf_scene_animation *anim = calloc(1, sizeof *anim);
  if (!anim)
    return scene_nomem(ctx);
  ctx->scene->animation = anim;
  size_t previous = scene_push_key(ctx, "animation");
  if ((s = scene_check_keys(ctx, obj, keys)) != SATF_OK ||
      (s = scene_key_number(ctx, obj, "fps", &r_fps, 0, 24.0, &anim->fps)) !=
          SATF_OK ||
      (s = scene_key_array(ctx, obj, "frames", 1, 0, 1 << 30, &frames, &n)) !=
          SATF_OK)
    goto done;
  if (n != 2) {
    s = scene_fail_key(ctx, "frames", SATF_ERR_FORMAT,
                       "expected [first, last], got %d entries", n);
    goto done;
  }
  double range[2];
  size_t inner = scene_push_key(ctx, "frames");
  for (int i = 0; i < 2 && s == SATF_OK; i++) {
    size_t item = scene_push_index(ctx, i);
    s = scene_number(ctx, cJSON_GetArrayItem(frames, i), &r_frame, &range[i]);
    scene_pop(ctx, item);
  }
  if (s == SATF_OK && range[1] < range[0])
    s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                   "the last frame %.0f is before the first frame %.0f",
                   range[1], range[0]);
  scene_pop(ctx, inner);
  if (s == SATF_OK) {
    anim->first = (int)range[0];
    anim->last = (int)range[1];
  }
done:
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_anim_keys_array(scene_ctx *ctx, const cJSON *obj,
                                  const cJSON **arr, int *count) {
  *arr = NULL;
  *count = 0;
  if (!cJSON_GetObjectItemCaseSensitive(obj, "keys"))
    return SATF_OK;
  satf_scene_animation *anim = ctx->scene->animation;
  if (!anim)
    return scene_fail_key(ctx, "keys", SATF_ERR_FORMAT,
                          "keyframes need a top-level \"animation\" object "
                          "giving the frame range");
  satf_status s =
      scene_key_array(ctx, obj, "keys", 1, 1, SATF_SCENE_MAX_KEYS, arr, count);
  if (s != SATF_OK)
    return s;
  /* Counted before anything is allocated for them. */
  if (anim->total_keys + *count > SATF_SCENE_MAX_KEYS_TOTAL)
    return scene_fail_key(ctx, "keys", SATF_ERR_ARGUMENT,
                          "brings the scene to %ld keys, over the limit of %d",
                          anim->total_keys + *count, SATF_SCENE_MAX_KEYS_TOTAL);
  anim->total_keys += *count;
  return SATF_OK;
}

satf_status scene_anim_key_frame(scene_ctx *ctx, const cJSON *key, int index,
                                 double previous, double *frame) {
  if (!cJSON_IsObject(key))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(key));
  const satf_scene_animation *anim = ctx->scene->animation;
  const scene_range range = {anim->first, anim->last, 0, 0};
  satf_status s = scene_key_number(ctx, key, "frame", &range, 1, 0.0, frame);
  if (s == SATF_OK && index > 0 && !(*frame > previous))
    s = scene_fail_key(ctx, "frame", SATF_ERR_ARGUMENT,
                       "%g is not after the previous key's frame %g; key "
                       "frames must increase",
                       *frame, previous);
  return s;
}

satf_status scene_anim_reject_fixed(scene_ctx *ctx, const cJSON *obj,
                                    const char *const *fixed,
                                    const char *what) {
  for (const char *const *k = fixed; *k; k++)
    if (cJSON_GetObjectItemCaseSensitive(obj, *k))
      return scene_fail_key(ctx, *k, SATF_ERR_FORMAT, "cannot be animated; %s",
                            what);
  return SATF_OK;
}

/* ---- prototypes ---- */

static satf_status count_mismatch(scene_ctx *ctx, const char *key, int got,
                                  int want, const char *unit) {
  return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT,
                        "has %d %s but the static %s has %d; keys keep the "
                        "counts",
                        got, unit, key, want);
}

static satf_status parse_prototype_key(scene_ctx *ctx, const cJSON *e,
                                       const satf_scene_cluster *c,
                                       scene_proto_key *key) {
  static const char *const keys[] = {"frame", "trajectory", "a",
                                     "b",     "twist",      NULL};
  static const char *const fixed[] = {"shell", "density", NULL};
  satf_status s;
  if ((s = scene_check_keys(ctx, e, keys)) != SATF_OK ||
      (s = scene_anim_reject_fixed(ctx, e, fixed,
                                   "a prototype key may give trajectory, a, "
                                   "b and twist")) != SATF_OK)
    return s;
  if (cJSON_GetObjectItemCaseSensitive(e, "trajectory")) {
    satf_scene_cluster tmp = {0};
    s = scene_parse_trajectory(ctx, e, &tmp);
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
    s = scene_parse_cluster_curve(ctx, e, names[i], &tmp);
    *values[i] = tmp.values;
    if (s == SATF_OK && tmp.count != statics[i]->count)
      s = count_mismatch(ctx, names[i], tmp.count, statics[i]->count,
                         "control values");
    if (s != SATF_OK)
      return s;
  }
  return SATF_OK;
}

satf_status scene_anim_parse_prototype_keys(scene_ctx *ctx, const cJSON *obj,
                                            int index,
                                            const satf_scene_cluster *c) {
  const cJSON *arr;
  int n;
  satf_status s = scene_anim_keys_array(ctx, obj, &arr, &n);
  if (s != SATF_OK || n == 0)
    return s;
  satf_scene_animation *anim = ctx->scene->animation;
  if (!anim->protos) {
    anim->protos =
        calloc((size_t)ctx->scene->n_macro_clusters, sizeof *anim->protos);
    if (!anim->protos)
      return scene_nomem(ctx);
    anim->n_protos = ctx->scene->n_macro_clusters;
  }
  scene_proto_track *track = &anim->protos[index];
  track->frames = calloc((size_t)n, sizeof *track->frames);
  track->keys = calloc((size_t)n, sizeof *track->keys);
  if (!track->frames || !track->keys)
    return scene_nomem(ctx);
  track->n_keys = n;
  size_t previous = scene_push_key(ctx, "keys");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    if ((s = scene_anim_key_frame(ctx, e, i, i ? track->frames[i - 1] : 0.0,
                                  &track->frames[i])) == SATF_OK)
      s = parse_prototype_key(ctx, e, c, &track->keys[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

/* ---- instances ---- */

satf_status scene_anim_add_instance_track(scene_ctx *ctx, int macro_cluster,
                                          int instance, int n,
                                          scene_instance_track **out) {
  satf_scene_animation *anim = ctx->scene->animation;
  if (anim->n_instance_tracks == anim->instance_capacity) {
    int cap = anim->instance_capacity ? 2 * anim->instance_capacity : 16;
    scene_instance_track *grown =
        realloc(anim->instances, (size_t)cap * sizeof *grown);
    if (!grown)
      return scene_nomem(ctx);
    anim->instances = grown;
    anim->instance_capacity = cap;
  }
  scene_instance_track *t = &anim->instances[anim->n_instance_tracks++];
  memset(t, 0, sizeof *t);
  t->macro_cluster = macro_cluster;
  t->instance = instance;
  t->frames = calloc((size_t)n, sizeof *t->frames);
  t->keys = calloc((size_t)n, sizeof *t->keys);
  if (!t->frames || !t->keys)
    return scene_nomem(ctx);
  t->n_keys = n;
  *out = t;
  return SATF_OK;
}

/* ---- camera and lights ---- */

static satf_status parse_camera_key(scene_ctx *ctx, const cJSON *e,
                                    const satf_scene_camera *cam,
                                    scene_camera_key *key) {
  static const char *const keys[] = {"frame", "position", "target",
                                     "up",    "fov_y",    NULL};
  static const char *const fixed[] = {"near", "far", NULL};
  static const scene_range r_coord = {-SATF_SCENE_MAX_COORD,
                                      SATF_SCENE_MAX_COORD, 0, 0};
  static const scene_range r_fov = {0.1, 179, 0, 0};
  satf_scene_camera tmp = *cam;
  satf_status s;
  if ((s = scene_check_keys(ctx, e, keys)) != SATF_OK ||
      (s = scene_anim_reject_fixed(ctx, e, fixed,
                                   "a camera key may give position, target, "
                                   "up and fov_y")) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "position", 3, &r_coord, cam->position,
                         tmp.position)) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "target", 3, &r_coord, cam->target,
                         tmp.target)) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "up", 3, &r_coord, cam->up, tmp.up)) !=
          SATF_OK ||
      (s = scene_key_float(ctx, e, "fov_y", &r_fov, cam->fov_y, &tmp.fov_y)) !=
          SATF_OK ||
      (s = scene_check_camera_view(ctx, &tmp)) != SATF_OK)
    return s;
  /* The static up is normalized already; again could move its last bit. */
  if (!cJSON_GetObjectItemCaseSensitive(e, "up"))
    memcpy(tmp.up, cam->up, sizeof tmp.up);
  memcpy(key->position, tmp.position, sizeof key->position);
  memcpy(key->target, tmp.target, sizeof key->target);
  memcpy(key->up, tmp.up, sizeof key->up);
  key->fov_y = tmp.fov_y;
  return SATF_OK;
}

satf_status scene_anim_parse_camera_keys(scene_ctx *ctx, const cJSON *obj,
                                         const satf_scene_camera *cam) {
  const cJSON *arr;
  int n;
  satf_status s = scene_anim_keys_array(ctx, obj, &arr, &n);
  if (s != SATF_OK || n == 0)
    return s;
  scene_camera_track *track = &ctx->scene->animation->camera;
  track->frames = calloc((size_t)n, sizeof *track->frames);
  track->keys = calloc((size_t)n, sizeof *track->keys);
  if (!track->frames || !track->keys)
    return scene_nomem(ctx);
  track->n_keys = n;
  size_t previous = scene_push_key(ctx, "keys");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    if ((s = scene_anim_key_frame(ctx, e, i, i ? track->frames[i - 1] : 0.0,
                                  &track->frames[i])) == SATF_OK &&
        (s = parse_camera_key(ctx, e, cam, &track->keys[i])) == SATF_OK &&
        cJSON_GetObjectItemCaseSensitive(e, "position"))
      track->sets_position = 1;
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_anim_parse_light_keys(scene_ctx *ctx, const cJSON *obj,
                                        int index,
                                        const satf_scene_light *light) {
  static const char *const dir_keys[] = {"frame", "direction", "color",
                                         "intensity", NULL};
  static const char *const point_keys[] = {"frame", "position", "color",
                                           "intensity", NULL};
  static const char *const fixed[] = {"type", NULL};
  int point = light->type == SATF_SCENE_LIGHT_POINT;
  const cJSON *arr;
  int n;
  satf_status s = scene_anim_keys_array(ctx, obj, &arr, &n);
  if (s != SATF_OK || n == 0)
    return s;
  satf_scene_animation *anim = ctx->scene->animation;
  if (!anim->lights) {
    anim->lights = calloc((size_t)ctx->scene->n_lights, sizeof *anim->lights);
    if (!anim->lights)
      return scene_nomem(ctx);
    anim->n_lights = ctx->scene->n_lights;
  }
  scene_light_track *track = &anim->lights[index];
  track->frames = calloc((size_t)n, sizeof *track->frames);
  track->keys = calloc((size_t)n, sizeof *track->keys);
  if (!track->frames || !track->keys)
    return scene_nomem(ctx);
  track->n_keys = n;
  size_t previous = scene_push_key(ctx, "keys");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    satf_scene_light tmp = *light;
    if ((s = scene_anim_key_frame(ctx, e, i, i ? track->frames[i - 1] : 0.0,
                                  &track->frames[i])) == SATF_OK &&
        (s = scene_check_keys(ctx, e, point ? point_keys : dir_keys)) ==
            SATF_OK &&
        (s = scene_anim_reject_fixed(ctx, e, fixed,
                                     "a light key may give its direction or "
                                     "position, color and intensity")) ==
            SATF_OK &&
        (s = scene_parse_light_values(ctx, e, light, &tmp)) == SATF_OK) {
      scene_light_key *key = &track->keys[i];
      if (!point && !cJSON_GetObjectItemCaseSensitive(e, "direction"))
        memcpy(tmp.direction, light->direction, sizeof tmp.direction);
      memcpy(key->vector, point ? tmp.position : tmp.direction,
             sizeof key->vector);
      memcpy(key->color, tmp.color, sizeof key->color);
      key->intensity = tmp.intensity;
    }
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}
