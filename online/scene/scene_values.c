/* scene_values.c - typed, range-checked reads of JSON values for the scene
 * parser; every failure names the key path (scene_report.h). */
#include "scene_values.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *scene_type_name(const cJSON *item) {
  if (cJSON_IsNumber(item))
    return "a number";
  if (cJSON_IsString(item))
    return "a string";
  if (cJSON_IsBool(item))
    return "a boolean";
  if (cJSON_IsNull(item))
    return "null";
  if (cJSON_IsArray(item))
    return "an array";
  if (cJSON_IsObject(item))
    return "an object";
  return "an unknown value";
}

/* Levenshtein distance, for "did you mean" on short keys only. */
static int edit_distance(const char *a, const char *b) {
  size_t na = strlen(a), nb = strlen(b);
  if (na > 40 || nb > 40)
    return 99;
  int row[41];
  for (size_t j = 0; j <= nb; j++)
    row[j] = (int)j;
  for (size_t i = 1; i <= na; i++) {
    int diag = row[0];
    row[0] = (int)i;
    for (size_t j = 1; j <= nb; j++) {
      int up = row[j];
      int best = diag + (a[i - 1] != b[j - 1]);
      if (row[j] + 1 < best)
        best = row[j] + 1;
      if (row[j - 1] + 1 < best)
        best = row[j - 1] + 1;
      row[j] = best;
      diag = up;
    }
  }
  return row[nb];
}

static int is_allowed(const char *key, const char *const *allowed) {
  for (const char *const *k = allowed; *k; k++)
    if (strcmp(key, *k) == 0)
      return 1;
  return 0;
}

satf_status scene_check_keys(scene_ctx *ctx, const cJSON *obj,
                             const char *const *allowed) {
  char quoted[64];
  for (const cJSON *item = obj->child; item; item = item->next) {
    const char *key = item->string ? item->string : "";
    if (is_allowed(key, allowed)) {
      /* Only known keys can be duplicates that matter (cJSON would silently
       * use the first); at most one per known key passes this loop, so the
       * scan stays linear in the object size. */
      for (const cJSON *other = obj->child; other != item; other = other->next)
        if (other->string && strcmp(other->string, key) == 0)
          return scene_fail(ctx, SATF_ERR_FORMAT, "key \"%s\" appears twice",
                            key);
      continue;
    }
    const char *suggestion = NULL;
    int best = 3; /* suggest only within two edits */
    for (const char *const *k = allowed; *k; k++) {
      int d = edit_distance(key, *k);
      if (d < best)
        best = d, suggestion = *k;
    }
    size_t previous =
        scene_push_key(ctx, scene_quote(key, quoted, sizeof quoted));
    satf_status s = suggestion ? scene_warn(ctx,
                                            "unknown key (ignored); did you "
                                            "mean \"%s\"?",
                                            suggestion)
                               : scene_warn(ctx, "unknown key (ignored)");
    scene_pop(ctx, previous);
    if (s != SATF_OK)
      return s;
  }
  return SATF_OK;
}

satf_status scene_key_object(scene_ctx *ctx, const cJSON *obj, const char *key,
                             int required, const cJSON **out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  *out = NULL;
  if (!item) {
    return required ? scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                                     "missing required key")
                    : SATF_OK;
  }
  if (!cJSON_IsObject(item))
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                          "expected an object, got %s", scene_type_name(item));
  *out = item;
  return SATF_OK;
}

satf_status scene_key_array(scene_ctx *ctx, const cJSON *obj, const char *key,
                            int required, int min_count, int max_count,
                            const cJSON **out, int *count) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  *out = NULL;
  *count = 0;
  if (!item) {
    return required ? scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                                     "missing required key")
                    : SATF_OK;
  }
  if (!cJSON_IsArray(item))
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                          "expected an array, got %s", scene_type_name(item));
  int n = cJSON_GetArraySize(item);
  if (n < min_count || n > max_count)
    return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT,
                          "has %d entries, expected %d to %d", n, min_count,
                          max_count);
  *out = item;
  *count = n;
  return SATF_OK;
}

satf_status scene_number(scene_ctx *ctx, const cJSON *item,
                         const scene_range *range, double *out) {
  const char *want = range->integer ? "an integer" : "a number";
  if (!cJSON_IsNumber(item))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected %s, got %s", want,
                      scene_type_name(item));
  double v = item->valuedouble;
  if (!isfinite(v))
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "number is too large to represent (parsed as %g)", v);
  if (range->integer && v != floor(v))
    return scene_fail(ctx, SATF_ERR_FORMAT, "%.10g is not an integer", v);
  int below = range->lo_open ? !(v > range->lo) : !(v >= range->lo);
  if (below || !(v <= range->hi))
    return scene_fail(ctx, SATF_ERR_ARGUMENT,
                      "%.10g is out of range %c%.10g, %.10g]", v,
                      range->lo_open ? '(' : '[', range->lo, range->hi);
  *out = v;
  return SATF_OK;
}

satf_status scene_key_number(scene_ctx *ctx, const cJSON *obj, const char *key,
                             const scene_range *range, int required, double def,
                             double *out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  if (!item) {
    if (required)
      return scene_fail_key(ctx, key, SATF_ERR_FORMAT, "missing required key");
    *out = def;
    return SATF_OK;
  }
  size_t previous = scene_push_key(ctx, key);
  satf_status s = scene_number(ctx, item, range, out);
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_key_float(scene_ctx *ctx, const cJSON *obj, const char *key,
                            const scene_range *range, double def, float *out) {
  double v;
  satf_status s = scene_key_number(ctx, obj, key, range, 0, def, &v);
  if (s == SATF_OK)
    *out = (float)v;
  return s;
}

satf_status scene_key_int(scene_ctx *ctx, const cJSON *obj, const char *key,
                          const scene_range *range, int def, int *out) {
  double v;
  satf_status s = scene_key_number(ctx, obj, key, range, 0, def, &v);
  if (s == SATF_OK)
    *out = (int)v; /* ranges of int keys fit in an int */
  return s;
}

satf_status scene_key_bool(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int def, int *out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  if (!item) {
    *out = def;
    return SATF_OK;
  }
  if (!cJSON_IsBool(item))
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                          "expected true or false, got %s",
                          scene_type_name(item));
  *out = cJSON_IsTrue(item) ? 1 : 0;
  return SATF_OK;
}

satf_status scene_key_string(scene_ctx *ctx, const cJSON *obj, const char *key,
                             int required, const char **out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  *out = NULL;
  if (!item) {
    return required ? scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                                     "missing required key")
                    : SATF_OK;
  }
  if (!cJSON_IsString(item) || !item->valuestring)
    return scene_fail_key(ctx, key, SATF_ERR_FORMAT,
                          "expected a string, got %s", scene_type_name(item));
  if (item->valuestring[0] == '\0')
    return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT,
                          "must not be an empty string");
  *out = item->valuestring;
  return SATF_OK;
}

satf_status scene_key_enum(scene_ctx *ctx, const cJSON *obj, const char *key,
                           const char *const *names, int n, int def, int *out) {
  const char *text;
  satf_status s = scene_key_string(ctx, obj, key, 0, &text);
  if (s != SATF_OK)
    return s;
  *out = def;
  if (!text)
    return SATF_OK;
  for (int i = 0; i < n; i++) {
    if (strcmp(text, names[i]) == 0) {
      *out = i;
      return SATF_OK;
    }
  }
  char choices[256] = "", quoted[64];
  for (int i = 0; i < n; i++) {
    size_t used = strlen(choices);
    snprintf(choices + used, sizeof choices - used, "%s\"%s\"", i ? ", " : "",
             names[i]);
  }
  return scene_fail_key(ctx, key, SATF_ERR_ARGUMENT, "\"%s\" is not one of %s",
                        scene_quote(text, quoted, sizeof quoted), choices);
}

satf_status scene_vec(scene_ctx *ctx, const cJSON *item, int n,
                      const scene_range *range, float *out) {
  if (!cJSON_IsArray(item))
    return scene_fail(ctx, SATF_ERR_FORMAT,
                      "expected an array of %d numbers, got %s", n,
                      scene_type_name(item));
  int count = cJSON_GetArraySize(item);
  if (count != n)
    return scene_fail(ctx, SATF_ERR_FORMAT,
                      "expected an array of %d numbers, got %d entries", n,
                      count);
  int i = 0;
  for (const cJSON *e = item->child; e; e = e->next, i++) {
    double v;
    size_t previous = scene_push_index(ctx, i);
    satf_status s = scene_number(ctx, e, range, &v);
    scene_pop(ctx, previous);
    if (s != SATF_OK)
      return s;
    out[i] = (float)v;
  }
  return SATF_OK;
}

satf_status scene_key_vec(scene_ctx *ctx, const cJSON *obj, const char *key,
                          int n, const scene_range *range, const float *def,
                          float *out) {
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
  if (!item) {
    if (!def)
      return scene_fail_key(ctx, key, SATF_ERR_FORMAT, "missing required key");
    memcpy(out, def, (size_t)n * sizeof *out);
    return SATF_OK;
  }
  size_t previous = scene_push_key(ctx, key);
  satf_status s = scene_vec(ctx, item, n, range, out);
  scene_pop(ctx, previous);
  return s;
}

char *scene_copy_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *c = malloc(n);
  if (c)
    memcpy(c, s, n);
  return c;
}

char *scene_resolve_path(const char *base_dir, const char *path) {
  if (path[0] == '/' || !base_dir || !base_dir[0])
    return scene_copy_string(path);
  size_t nb = strlen(base_dir), np = strlen(path);
  int slash = base_dir[nb - 1] != '/';
  char *out = malloc(nb + (size_t)slash + np + 1);
  if (!out)
    return NULL;
  memcpy(out, base_dir, nb);
  if (slash)
    out[nb] = '/';
  memcpy(out + nb + (size_t)slash, path, np + 1);
  return out;
}

satf_status scene_key_path(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int required, const char *base_dir, char **out) {
  const char *text;
  satf_status s = scene_key_string(ctx, obj, key, required, &text);
  if (s != SATF_OK || !text)
    return s;
  *out = scene_resolve_path(base_dir, text);
  return *out ? SATF_OK : scene_nomem(ctx);
}

satf_status scene_key_copy(scene_ctx *ctx, const cJSON *obj, const char *key,
                           int required, char **out) {
  const char *text;
  satf_status s = scene_key_string(ctx, obj, key, required, &text);
  if (s != SATF_OK || !text)
    return s;
  *out = scene_copy_string(text);
  return *out ? SATF_OK : scene_nomem(ctx);
}
