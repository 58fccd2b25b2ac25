/* scene_parse_instance.c - the instance transforms of macro-clusters (SATF
 * sec. 3.1: clusters "derived from each other via simple transformations")
 * and their keyframes, and the transforms of meshes: a row-major matrix or
 * translate / rotate / scale, each key given the same way with the static
 * transform as its default. */
#include "scene_parse_instance.h"

#include <math.h>
#include <string.h>

#include "satf/math.h"
#include "scene_check.h"
#include "scene_interp.h"
#include "scene_transform.h"

static const scene_range R_COORD = {-SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD,
                                    0, 0};

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

/* The unit axis and the angle in radians of a TRS transform. */
static void rotation_of(const scene_xform *f, double axis[3],
                        double *angle_rad) {
  double len = scene_vec_length(f->axis);
  for (int k = 0; k < 3; k++)
    axis[k] = f->axis[k] / len;
  *angle_rad = f->degrees * (SATF_PI / 180.0);
}

/* inst.rotate, or def's rotation (none when def is NULL). */
static satf_status parse_rotate(scene_ctx *ctx, const cJSON *inst,
                                const scene_xform *def, scene_xform *out) {
  static const char *const keys[] = {"axis", "angle", NULL};
  static const scene_range r_angle = {-1e5, 1e5, 0, 0};
  static const float z_axis[3] = {0.0f, 0.0f, 1.0f};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, inst, "rotate", 0, &obj);
  memcpy(out->axis, def ? def->axis : z_axis, sizeof out->axis);
  out->degrees = def ? def->degrees : 0.0;
  if (s != SATF_OK || !obj)
    return s;
  size_t previous = scene_push_key(ctx, "rotate");
  float a[3];
  double degrees = 0.0;
  if ((s = scene_check_keys(ctx, obj, keys)) == SATF_OK &&
      (s = scene_key_vec(ctx, obj, "axis", 3, &R_COORD, NULL, a)) == SATF_OK &&
      (s = scene_key_number(ctx, obj, "angle", &r_angle, 1, 0.0, &degrees)) ==
          SATF_OK) {
    if (!(scene_vec_length(a) > 1e-9)) {
      s = scene_fail_key(ctx, "axis", SATF_ERR_ARGUMENT,
                         "has zero length; a rotation needs an axis");
    } else {
      memcpy(out->axis, a, sizeof out->axis);
      out->degrees = degrees;
    }
  }
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_scale(scene_ctx *ctx, const cJSON *inst,
                               const scene_xform *def, float scale[3]) {
  static const scene_range r_scale = {-1e4, 1e4, 0, 0};
  const cJSON *item = cJSON_GetObjectItemCaseSensitive(inst, "scale");
  float v[3] = {1.0f, 1.0f, 1.0f};
  if (def)
    memcpy(v, def->scale, sizeof v);
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

/* f->m from f's translate, rotate and scale (f->is_matrix == 0). */
static void xform_compose(scene_xform *f) {
  double translate[3], axis[3], angle_rad, scale[3];
  for (int k = 0; k < 3; k++) {
    translate[k] = f->translate[k];
    scale[k] = f->scale[k];
  }
  rotation_of(f, axis, &angle_rad);
  scene_matrix_trs(translate, axis, angle_rad, scale, f->m);
}

/* The transform of item (an instance or one of its keys); def is the
 * static transform a key defaults to, NULL for the instance itself. */
static satf_status parse_form(scene_ctx *ctx, const cJSON *item,
                              const scene_xform *def, scene_xform *out) {
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
  xform_compose(out);
  return SATF_OK;
}

/* Splits a key's transform into translation, rotation and stretch for
 * interpolation; T R S parts are taken as written, a matrix is split by its
 * polar decomposition. */
static void split_form(const scene_xform *f, scene_xform_key *key) {
  key->form = *f;
  for (int i = 0; i < 3; i++)
    key->translate[i] = f->m[4 * i + 3];
  if (!f->is_matrix) {
    double axis[3], angle_rad;
    rotation_of(f, axis, &angle_rad);
    scene_quat_from_axis_angle(axis, angle_rad, key->rotation);
    for (int k = 0; k < 9; k++)
      key->stretch[k] = (k % 4 == 0) ? f->scale[k / 4] : 0.0f;
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

static satf_status read_instance_key(scene_ctx *ctx, const cJSON *e, void *out,
                                     const void *user) {
  static const char *const keys[] = {"frame",  "matrix", "translate",
                                     "rotate", "scale",  NULL};
  scene_xform key = {0};
  satf_status s;
  if ((s = scene_check_keys(ctx, e, keys)) == SATF_OK &&
      (s = parse_form(ctx, e, user, &key)) == SATF_OK)
    split_form(&key, out);
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
  scene_xform form = {0};
  satf_status s;
  if ((s = scene_check_keys(ctx, item, keys)) != SATF_OK ||
      (s = parse_form(ctx, item, NULL, &form)) != SATF_OK)
    return s;
  memcpy(out->m, form.m, sizeof out->m);
  scene_instance_track scratch = {0}, *t = &scratch;
  if (scene_tracks_has_keys(ctx, item)) {
    t = scene_anim_add_instance(ctx->scene->animation, macro_cluster, instance);
    if (!t)
      return scene_nomem(ctx);
    t->base = form;
  }
  return scene_tracks_read(ctx, item, sizeof(scene_xform_key),
                           read_instance_key, &form, &t->track);
}

satf_status scene_parse_transform(scene_ctx *ctx, const cJSON *item,
                                  float m[16]) {
  static const char *const keys[] = {"matrix", "translate", "rotate", "scale",
                                     NULL};
  if (!cJSON_IsObject(item))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(item));
  scene_xform form = {0};
  satf_status s;
  if ((s = scene_check_keys(ctx, item, keys)) != SATF_OK ||
      (s = parse_form(ctx, item, NULL, &form)) != SATF_OK)
    return s;
  memcpy(m, form.m, 16 * sizeof(float));
  return SATF_OK;
}
