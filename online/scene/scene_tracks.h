/* scene_tracks.h - reading keyframes (samples/README.md, "Animation"): the
 * root "animation" object, and the one reader of a "keys" array that every
 * animated object (prototype, instance, camera, light) goes through. What a
 * single key may hold is the caller's: a callback reads it. */
#ifndef SATF_ONLINE_SCENE_TRACKS_H
#define SATF_ONLINE_SCENE_TRACKS_H

#include "scene_anim.h"
#include "scene_values.h"

/* root.animation into ctx->scene->animation (left NULL when absent). */
satf_status scene_tracks_parse_settings(scene_ctx *ctx, const cJSON *root);

/* 1 when obj has "keys" and the scene an animation to put them in: the
 * caller then has a track to read them into. */
int scene_tracks_has_keys(const scene_ctx *ctx, const cJSON *obj);

/* Reads one key (an object whose "frame" has been read; the ctx path ends
 * in "keys[i]") into out (key_size bytes, zeroed). user is the caller's. */
typedef satf_status (*scene_key_reader)(scene_ctx *ctx, const cJSON *key,
                                        void *out, const void *user);

/* obj.keys into track: absent gives no keys; present it needs the
 * animation object and must be an array of 1..SATF_SCENE_MAX_KEYS objects,
 * counted against the scene-wide key limit, each with a "frame" in the
 * animation's range after the previous key's, read by read_key. track owns
 * what was allocated even when this fails. */
satf_status scene_tracks_read(scene_ctx *ctx, const cJSON *obj, size_t key_size,
                              scene_key_reader read_key, const void *user,
                              scene_track *track);

/* Fails with "KEY: cannot be animated; what" for the first of obj's keys
 * listed in fixed (the static-only keys of that object). */
satf_status scene_tracks_reject_fixed(scene_ctx *ctx, const cJSON *obj,
                                      const char *const *fixed,
                                      const char *what);

#endif
