/* scene_tracks.c - the "animation" object and the generic "keys" reader. */
#include "scene_tracks.h"

#include <stdlib.h>
#include <string.h>

satf_status scene_tracks_parse_settings(scene_ctx *ctx, const cJSON *root) {
  static const char *const keys[] = {"fps", "frames", NULL};
  static const scene_range r_fps = {0, SATF_SCENE_MAX_FPS, 1, 0};
  static const scene_range r_frame = {-SATF_SCENE_MAX_FRAME,
                                      SATF_SCENE_MAX_FRAME, 0, 1};
  const cJSON *obj, *frames;
  int n;
  satf_status s = scene_key_object(ctx, root, "animation", 0, &obj);
  if (s != SATF_OK || !obj)
    return s;
  satf_scene_animation *anim = scene_anim_create(0.0, 0, 0);
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

int scene_tracks_has_keys(const scene_ctx *ctx, const cJSON *obj) {
  return ctx->scene->animation &&
         cJSON_GetObjectItemCaseSensitive(obj, "keys") != NULL;
}

/* obj.keys as an array of *count entries, counted before anything is
 * allocated for them. */
static satf_status keys_array(scene_ctx *ctx, const cJSON *obj,
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
  if (anim->total_keys + *count > SATF_SCENE_MAX_KEYS_TOTAL)
    return scene_fail_key(ctx, "keys", SATF_ERR_ARGUMENT,
                          "brings the scene to %ld keys, over the limit of %d",
                          anim->total_keys + *count, SATF_SCENE_MAX_KEYS_TOTAL);
  anim->total_keys += *count;
  return SATF_OK;
}

/* keys[index].frame: a number in the frame range, after previous. */
static satf_status key_frame(scene_ctx *ctx, const cJSON *key, int index,
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

satf_status scene_tracks_read(scene_ctx *ctx, const cJSON *obj, size_t key_size,
                              scene_key_reader read_key, const void *user,
                              scene_track *track) {
  const cJSON *arr;
  int n;
  satf_status s = keys_array(ctx, obj, &arr, &n);
  if (s != SATF_OK || n == 0)
    return s;
  if (!scene_track_alloc(track, n, key_size))
    return scene_nomem(ctx);
  size_t previous = scene_push_key(ctx, "keys");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    if ((s = key_frame(ctx, e, i, i ? track->frames[i - 1] : 0.0,
                       &track->frames[i])) == SATF_OK)
      s = read_key(ctx, e, (char *)track->keys + (size_t)i * key_size, user);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_tracks_reject_fixed(scene_ctx *ctx, const cJSON *obj,
                                      const char *const *fixed,
                                      const char *what) {
  for (const char *const *k = fixed; *k; k++)
    if (cJSON_GetObjectItemCaseSensitive(obj, *k))
      return scene_fail_key(ctx, *k, SATF_ERR_FORMAT, "cannot be animated; %s",
                            what);
  return SATF_OK;
}
