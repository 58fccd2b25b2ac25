/* scene_values.h - typed, validated reads from a cJSON tree ("a number in
 * [0, 1]", "an array of 3 numbers", "a path resolved against the scene's
 * directory") that fail or warn through scene_report.h with the key path
 * they concern. Knows nothing about the scene schema itself. */
#ifndef SATF_ONLINE_SCENE_VALUES_H
#define SATF_ONLINE_SCENE_VALUES_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "scene_report.h"

/* Allowed values of a number: [lo, hi], or (lo, hi] when lo_open. */
typedef struct scene_range {
  double lo, hi;
  int lo_open;
  int integer;
} scene_range;

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

#endif
