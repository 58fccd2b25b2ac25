/* scene_json.h - typed, validated reads from a cJSON tree that report
 * errors and warnings with the key path they concern ("NAME: a.b[2].c:
 * what is wrong"). Owns the key-path stack and the warning list while a
 * scene is being parsed; knows nothing about the scene schema itself. */
#ifndef SATF_ONLINE_SCENE_JSON_H
#define SATF_ONLINE_SCENE_JSON_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "satf/satf.h"
#include "satf/scene.h"

#define SCENE_PATH_MAX 512
#define SCENE_WARNINGS_KEPT 256

typedef struct scene_ctx {
  const char *name;          /* prefixes every message */
  char path[SCENE_PATH_MAX]; /* key path of the value being read */
  size_t len;
  satf_error *err;
  satf_scene *scene;    /* receives warnings */
  int warnings_dropped; /* beyond SCENE_WARNINGS_KEPT */
} scene_ctx;

/* Allowed values of a number: [lo, hi], or (lo, hi] when lo_open. */
typedef struct scene_range {
  double lo, hi;
  int lo_open;
  int integer;
} scene_range;

/* Appends ".key" (or "key" at the root) / "[index]"; returns the previous
 * length for scene_pop. */
size_t scene_push_key(scene_ctx *ctx, const char *key);
size_t scene_push_index(scene_ctx *ctx, int index);
void scene_pop(scene_ctx *ctx, size_t previous);

/* Fails with "NAME: PATH: message" (PATH of the current value). */
satf_status scene_fail(scene_ctx *ctx, satf_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Same for the child `key` of the current value. */
satf_status scene_fail_key(scene_ctx *ctx, const char *key, satf_status status,
                           const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
satf_status scene_nomem(scene_ctx *ctx);
/* Records "NAME: PATH: message" as a warning; fails only on NOMEM. */
satf_status scene_warn(scene_ctx *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Adds "N more warnings not shown" when warnings were dropped. */
satf_status scene_warn_dropped(scene_ctx *ctx);

/* Escapes and shortens text from the file for a message. */
const char *scene_quote(const char *text, char *buf, size_t size);
const char *scene_type_name(const cJSON *item);

/* Warns about each key of obj not in allowed (NULL-terminated), suggesting
 * a close known key; fails on a key given twice. */
satf_status scene_check_keys(scene_ctx *ctx, const cJSON *obj,
                             const char *const *allowed);

/* Typed reads of obj[key]. A missing key yields the default (or fails with
 * "missing required key" when required); a wrong type, a non-finite
 * number or a value out of range fails. */
satf_status scene_key_object(scene_ctx *ctx, const cJSON *obj, const char *key,
                             int required, const cJSON **out);
satf_status scene_key_array(scene_ctx *ctx, const cJSON *obj, const char *key,
                            int required, int min_count, int max_count,
                            const cJSON **out, int *count);
satf_status scene_number(scene_ctx *ctx, const cJSON *item,
                         const scene_range *range, double *out);
satf_status scene_key_number(scene_ctx *ctx, const cJSON *obj, const char *key,
                             const scene_range *range, int required, double def,
                             double *out);
satf_status scene_key_float(scene_ctx *ctx, const cJSON *obj, const char *key,
                            const scene_range *range, double def, float *out);
satf_status scene_key_int(scene_ctx *ctx, const cJSON *obj, const char *key,
                          const scene_range *range, int def, int *out);
satf_status scene_key_bool(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int def, int *out);
/* A non-empty string; *out NULL when absent and not required. */
satf_status scene_key_string(scene_ctx *ctx, const cJSON *obj, const char *key,
                             int required, const char **out);
/* One of names[0..n): *out is its index, def when absent. */
satf_status scene_key_enum(scene_ctx *ctx, const cJSON *obj, const char *key,
                           const char *const *names, int n, int def, int *out);
/* An array of exactly n numbers in range; def (n values) when absent, or
 * required when def is NULL. */
satf_status scene_vec(scene_ctx *ctx, const cJSON *item, int n,
                      const scene_range *range, float *out);
satf_status scene_key_vec(scene_ctx *ctx, const cJSON *obj, const char *key,
                          int n, const scene_range *range, const float *def,
                          float *out);

/* A string obj[key] resolved against base_dir (scene_resolve_path), or a
 * plain copy; *out stays NULL when absent and not required. */
satf_status scene_key_path(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int required, const char *base_dir, char **out);
satf_status scene_key_copy(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int required, char **out);

/* base_dir + "/" + path for a relative path, a copy otherwise; NULL on
 * allocation failure. */
char *scene_resolve_path(const char *base_dir, const char *path);
char *scene_copy_string(const char *s);
double scene_vec_length(const float v[3]);

#endif
