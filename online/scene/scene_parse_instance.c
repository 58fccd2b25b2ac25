/* scene_instance.c - the instance transforms of macro-clusters (SATF sec.
 * 3.1: clusters "derived from each other via simple transformations") and
 * their keyframes: a row-major matrix or translate / rotate / scale, each
 * key given the same way with the static transform as its default. */
#include <math.h>
#include <string.h>

#include "scene_anim.h"
#include "scene_interp.h"
#include "scene_parse.h"
#include "scene_transform.h"

#define PI 3.14159265358979323846

static const scene_range R_COORD = {-SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD,
                                    0, 0};

/* A transform as written: a matrix, or the parts of T R S. */
typedef struct instance_form {
  int is_matrix;
  float m[16]; /* composed */
  float translate[3];
  double axis[3], angle_rad;
  double scale[3];
} instance_form;

static const char *const trs_keys[] = {"translate", "rotate", "scale", NULL};

static satf_status parse_matrix(scene_ctx *ctx, const cJSON *item,
                                float m[16]) {
  size_t previous = scene_push_key(ctx, "matrix");
  satf_status s = scene_vec(ctx, item, 16, &R_COORD, m);
  if (s == SATF_OK && scene_matrix_projective_error(m) > 1e-6)
    s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                   "the last row must be [0, 0, 0, 1] (an affine transform), "
                   "got [%g, %g, %g, %g]",
                   m[12], m[13], m[14], m[15]);
  if (s == SATF_OK && !(fabs(scene_matrix_det3(m)) >= 1e-12))
    s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                   "is singular (determinant %g of the 3x3 part)",
                   scene_matrix_det3(m));
  scene_pop(ctx, previous);
  return s;
}

/* inst.rotate, or def's rotation (the identity when def is NULL). */
static satf_status parse_rotate(scene_ctx *ctx, const cJSON *inst,
                                const instance_form *def, instance_form *out) {
  static const char *const keys[] = {"axis", "angle", NULL};
  static const scene_range r_angle = {-1e5, 1e5, 0, 0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, inst, "rotate", 0, &obj);
  if (def) {
    memcpy(out->axis, def->axis, sizeof out->axis);
    out->angle_rad = def->angle_rad;
  } else {
    out->axis[0] = out->axis[1] = 0.0;
    out->axis[2] = 1.0;
    out->angle_rad = 0.0;
  }
  if (s != SATF_OK || !obj)
    return s;
  size_t previous = scene_push_key(ctx, "rotate");
  float a[3];
  double degrees = 0.0;
  if ((s = scene_check_keys(ctx, obj, keys)) == SATF_OK &&
      (s = scene_key_vec(ctx, obj, "axis", 3, &R_COORD, NULL, a)) == SATF_OK &&
      (s = scene_key_number(ctx, obj, "angle", &r_angle, 1, 0.0, &degrees)) ==
          SATF_OK) {
    double len = scene_vec_length(a);
    if (!(len > 1e-9)) {
      s = scene_fail_key(ctx, "axis", SATF_ERR_ARGUMENT,
                         "has zero length; a rotation needs an axis");
    } else {
      for (int k = 0; k < 3; k++)
        out->axis[k] = a[k] / len;
      out->angle_rad = degrees * (PI / 180.0);
    }
  }
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_scale(scene_ctx *ctx, const cJSON *inst,
                               const instance_form *def, double scale[3]) {
  static const scene_range r_scale = {-1e4, 1e4, 0, 0};
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(inst, "scale");
  float v[3] = {1.0f, 1.0f, 1.0f};
  if (def)
    for (int k = 0; k < 3; k++)
      v[k] = (float)def->scale[k];
  satf_status s = SATF_OK;
  size_t previous = scene_push_key(ctx, "scale");
  if (item && cJSON_IsNumber(item)) {
    double u;
    s = scene_number(ctx, item, &r_scale, &u);
    v[0] = v[1] = v[2] = (float)u;
  } else if (item) {
    s = scene_vec(ctx, item, 3, &r_scale, v);
  }
  for (int k = 0; k < 3 && s == SATF_OK; k++) {
    if (!(fabs(v[k]) >= 1e-4))
      s = scene_fail(ctx, SATF_ERR_ARGUMENT,
                     "%g is too close to zero (|scale| must be >= 1e-4)", v[k]);
    scale[k] = v[k];
  }
  scene_pop(ctx, previous);
  return s;
}

/* The transform of item (an instance or one of its keys); def is the
 * static transform a key defaults to, NULL for the instance itself. */
static satf_status parse_form(scene_ctx *ctx, const cJSON *item,
                              const instance_form *def, instance_form *out) {
  static const float zero[3] = {0.0f, 0.0f, 0.0f};
  const cJSON *matrix = cJSON_GetObjectItemCaseSensitive(item, "matrix");
  if (matrix) {
    for (int k = 0; trs_keys[k]; k++)
      if (cJSON_GetObjectItemCaseSensitive(item, trs_keys[k]))
        return scene_fail(ctx, SATF_ERR_FORMAT,
                          "\"matrix\" cannot be combined with \"%s\"; give "
                          "one or the other",
                          trs_keys[k]);
    out->is_matrix = 1;
    return parse_matrix(ctx, matrix, out->m);
  }
  if (def && def->is_matrix) {
    for (int k = 0; trs_keys[k]; k++)
      if (cJSON_GetObjectItemCaseSensitive(item, trs_keys[k]))
        return scene_fail_key(ctx, trs_keys[k], SATF_ERR_FORMAT,
                              "the instance is given as a \"matrix\", so its "
                              "keys must give a \"matrix\" too");
    *out = *def;
    return SATF_OK;
  }
  satf_status s;
  out->is_matrix = 0;
  if ((s = scene_key_vec(ctx, item, "translate", 3, &R_COORD,
                         def ? def->translate : zero, out->translate)) !=
          SATF_OK ||
      (s = parse_rotate(ctx, item, def, out)) != SATF_OK ||
      (s = parse_scale(ctx, item, def, out->scale)) != SATF_OK)
    return s;
  double translate[3];
  for (int k = 0; k < 3; k++)
    translate[k] = out->translate[k];
  scene_matrix_trs(translate, out->axis, out->angle_rad, out->scale, out->m);
  return SATF_OK;
}

/* Splits a key's transform into translation, rotation and stretch for
 * interpolation; T R S parts are taken as written, a matrix is split by its
 * polar decomposition. */
static void split_form(const instance_form *f, scene_xform_key *key) {
  memcpy(key->m, f->m, sizeof key->m);
  for (int i = 0; i < 3; i++)
    key->translate[i] = f->m[4 * i + 3];
  if (!f->is_matrix) {
    scene_quat_from_axis_angle(f->axis, f->angle_rad, key->rotation);
    for (int k = 0; k < 9; k++)
      key->stretch[k] = (k % 4 == 0) ? (float)f->scale[k / 4] : 0.0f;
    return;
  }
  double m3[9], r[9], s[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      m3[3 * i + j] = f->m[4 * i + j];
  scene_polar_decompose(m3, r, s);
  scene_quat_from_matrix(r, key->rotation);
  for (int k = 0; k < 9; k++)
    key->stretch[k] = (float)s[k];
}

static satf_status parse_instance_keys(scene_ctx *ctx, const cJSON *item,
                                       int macro_cluster, int instance,
                                       const instance_form *form) {
  static const char *const keys[] = {"frame",  "matrix", "translate",
                                     "rotate", "scale",  NULL};
  const cJSON *arr;
  int n;
  scene_instance_track *track;
  satf_status s = scene_anim_keys_array(ctx, item, &arr, &n);
  if (s != SATF_OK || n == 0)
    return s;
  if ((s = scene_anim_add_instance_track(ctx, macro_cluster, instance, n,
                                         &track)) != SATF_OK)
    return s;
  size_t previous = scene_push_key(ctx, "keys");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    instance_form key = {0};
    if ((s = scene_anim_key_frame(ctx, e, i, i ? track->frames[i - 1] : 0.0,
                                  &track->frames[i])) == SATF_OK &&
        (s = scene_check_keys(ctx, e, keys)) == SATF_OK &&
        (s = parse_form(ctx, e, form, &key)) == SATF_OK)
      split_form(&key, &track->keys[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_parse_instance(scene_ctx *ctx, const cJSON *item,
                                 int macro_cluster, int instance,
                                 satf_scene_instance *out) {
  static const char *const keys[] = {"matrix", "translate", "rotate",
                                     "scale",  "keys",      NULL};
  if (!cJSON_IsObject(item))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(item));
  instance_form form = {0};
  satf_status s;
  if ((s = scene_check_keys(ctx, item, keys)) != SATF_OK ||
      (s = parse_form(ctx, item, NULL, &form)) != SATF_OK)
    return s;
  memcpy(out->m, form.m, sizeof out->m);
  return parse_instance_keys(ctx, item, macro_cluster, instance, &form);
}

satf_status scene_parse_transform(scene_ctx *ctx, const cJSON *item,
                                  float m[16]) {
  static const char *const keys[] = {"matrix", "translate", "rotate", "scale",
                                     NULL};
  if (!cJSON_IsObject(item))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(item));
  instance_form form = {0};
  satf_status s;
  if ((s = scene_check_keys(ctx, item, keys)) != SATF_OK ||
      (s = parse_form(ctx, item, NULL, &form)) != SATF_OK)
    return s;
  memcpy(m, form.m, 16 * sizeof(float));
  return SATF_OK;
}
