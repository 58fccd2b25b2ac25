/* scene_parse.c - the scene schema (samples/README.md is its reference)
 * apart from the hair (scene_parse_cluster.c, scene_parse_instance.c): the
 * root, material, effects, camera and lights with their keys, image and
 * meshes. The simple fields' keys, defaults and ranges are the tables of
 * scene_fields.c; what is here is the rest. */
#include "scene_parse.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "satf/math.h"
#include "scene_check.h"
#include "scene_fields.h"

static const scene_range R_COORD = {-SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD,
                                    0, 0};
static const scene_range R_UNIT = {0, 1, 0, 0};
static const float BACKGROUND[3] = {0.1f, 0.1f, 0.12f};
static const float SKIN[3] = {0.55f, 0.42f, 0.36f};
/* ---- material (SATF eq. 9-12, Scheuermann 2004) ---- */

/* The material's keys that are more than a number: the shift both
 * highlights default to, the shading model and the optional absorption. */
static satf_status read_material_other(scene_ctx *ctx, const cJSON *obj,
                                       const scene_field *row, void *base,
                                       void *user) {
  static const char *const models[] = {"kk", "physical"};
  static const float no_absorption[3] = {0.0f, 0.0f, 0.0f};
  satf_scene_material *m = base;
  float *shift = user;
  if (strcmp(row->key, "shift") == 0)
    return scene_key_float(ctx, obj, row->key, &row->range, 0.1, shift);
  if (strcmp(row->key, "shift_I") == 0)
    return scene_key_float(ctx, obj, row->key, &row->range, *shift,
                           &m->shift_I);
  if (strcmp(row->key, "shift_II") == 0)
    return scene_key_float(ctx, obj, row->key, &row->range, *shift,
                           &m->shift_II);
  if (strcmp(row->key, "model") == 0) {
    int model;
    satf_status s =
        scene_key_enum(ctx, obj, row->key, models, SATF_MATERIAL_MODEL_COUNT,
                       SATF_MATERIAL_KK, &model);
    m->model = (satf_material_model)model;
    return s;
  }
  /* absorption: replaces the melanin when given */
  m->has_absorption = cJSON_GetObjectItemCaseSensitive(obj, row->key) != NULL;
  return scene_key_vec(ctx, obj, row->key, 3, &row->range, no_absorption,
                       m->absorption);
}

/* SATF eq. 9-12 and Scheuermann 2004; the fibre of the physical model with
 * the meanings of Cycles' Principled Hair, so a scene and a Cycles render
 * given the same numbers show the same hair (scene_fields.c). */
static satf_status parse_material(scene_ctx *ctx, const cJSON *root,
                                  satf_scene_material *m) {
  static const cJSON empty = {0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, root, "material", 0, &obj);
  if (s != SATF_OK)
    return s;
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "material");
  float shift = 0.1f;
  s = scene_fields_read(ctx, obj, &SCENE_MATERIAL, m, read_material_other,
                        &shift);
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_effects(scene_ctx *ctx, const cJSON *root,
                                 satf_scene_effects *e) {
  static const cJSON empty = {0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, root, "effects", 0, &obj);
  if (s != SATF_OK)
    return s;
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "effects");
  s = scene_fields_read(ctx, obj, &SCENE_EFFECTS, e, NULL, NULL);
  scene_pop(ctx, previous);
  return s;
}

/* ---- camera, lights, image ---- */

static void frame_bounds(const satf_scene *scene, float fov_y_deg,
                         float target[3], float position[3]) {
  float lo[3], hi[3];
  satf_scene_bounds(scene, lo, hi);
  float d[3];
  for (int k = 0; k < 3; k++) {
    target[k] = 0.5f * (lo[k] + hi[k]);
    d[k] = hi[k] - lo[k];
  }
  /* Back off along +z until the bounding sphere fits the vertical fov. */
  double radius = 0.5 * scene_vec_length(d);
  if (radius < 1e-3)
    radius = 1e-3;
  double dist = 1.1 * radius / sin(0.5 * fov_y_deg * SATF_PI / 180.0);
  position[0] = target[0];
  position[1] = target[1];
  position[2] = (float)(target[2] + dist);
}

/* A camera key over the static camera `user`: position, target, up and
 * fov_y, the view checked as the static one is. */
static satf_status read_camera_key(scene_ctx *ctx, const cJSON *e, void *out,
                                   const void *user) {
  static const char *const keys[] = {"frame", "position", "target",
                                     "up",    "fov_y",    NULL};
  static const char *const fixed[] = {"near", "far", NULL};
  static const char *const given[] = {"position", "target", "up", "fov_y"};
  const scene_field *fov = scene_field_find(&SCENE_CAMERA, "fov_y");
  const satf_scene_camera *cam = user;
  scene_camera_key *key = out;
  satf_scene_camera tmp = *cam;
  satf_status s;
  if ((s = scene_check_keys(ctx, e, keys)) != SATF_OK ||
      (s = scene_tracks_reject_fixed(ctx, e, fixed,
                                     "a camera key may give position, "
                                     "target, up and fov_y")) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "position", 3, &R_COORD, cam->position,
                         tmp.position)) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "target", 3, &R_COORD, cam->target,
                         tmp.target)) != SATF_OK ||
      (s = scene_key_vec(ctx, e, "up", 3, &R_COORD, cam->up, tmp.up)) !=
          SATF_OK ||
      (s = scene_key_float(ctx, e, fov->key, &fov->range, cam->fov_y,
                           &tmp.fov_y)) != SATF_OK ||
      (s = scene_check_camera_view(ctx, &tmp)) != SATF_OK)
    return s;
  /* The static up is normalized already; again could move its last bit. */
  if (!cJSON_GetObjectItemCaseSensitive(e, "up"))
    memcpy(tmp.up, cam->up, sizeof tmp.up);
  memcpy(key->position, tmp.position, sizeof key->position);
  memcpy(key->target, tmp.target, sizeof key->target);
  memcpy(key->up, tmp.up, sizeof key->up);
  key->fov_y = tmp.fov_y;
  for (int i = 0; i < 4; i++)
    if (cJSON_GetObjectItemCaseSensitive(e, given[i]))
      key->given |= 1u << i; /* SCENE_GIVES_POSITION .. SCENE_GIVES_FOV */
  return SATF_OK;
}

static satf_status parse_camera_keys(scene_ctx *ctx, const cJSON *obj,
                                     const satf_scene_camera *cam) {
  scene_track scratch = {0}, *t = &scratch;
  if (scene_tracks_has_keys(ctx, obj))
    t = &ctx->scene->animation->camera;
  satf_status s = scene_tracks_read(ctx, obj, sizeof(scene_camera_key),
                                    read_camera_key, cam, t);
  const scene_camera_key *keys = t->keys;
  for (int i = 0; s == SATF_OK && i < t->n_keys; i++)
    if (keys[i].given & SCENE_GIVES_POSITION)
      ctx->scene->animation->camera_sets_position = 1;
  return s;
}

static satf_status parse_camera(scene_ctx *ctx, const cJSON *root,
                                satf_scene_camera *cam) {
  static const cJSON empty = {0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, root, "camera", 0, &obj);
  if (s != SATF_OK)
    return s;
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "camera");
  float auto_target[3], auto_position[3];
  /* up, fov_y, near and far; then the target and the position, whose
   * defaults follow from the bounds and fov_y */
  if ((s = scene_fields_read(ctx, obj, &SCENE_CAMERA, cam, NULL, NULL)) !=
      SATF_OK)
    goto done;
  frame_bounds(ctx->scene, cam->fov_y, auto_target, auto_position);
  cam->automatic = !cJSON_GetObjectItemCaseSensitive(obj, "position");
  if ((s = scene_key_vec(ctx, obj, "target", 3, &R_COORD, auto_target,
                         cam->target)) != SATF_OK)
    goto done;
  /* Framed from the bounds, but centred on the target the file gave. */
  for (int k = 0; k < 3; k++)
    auto_position[k] += cam->target[k] - auto_target[k];
  if ((s = scene_key_vec(ctx, obj, "position", 3, &R_COORD, auto_position,
                         cam->position)) != SATF_OK)
    goto done;
  if ((s = scene_check_camera_view(ctx, cam)) != SATF_OK)
    goto done;
  if (cam->near_clip > 0 && cam->far_clip > 0 &&
      !(cam->far_clip > cam->near_clip))
    s = scene_fail_key(ctx, "far", SATF_ERR_ARGUMENT,
                       "%g must be greater than near (%g)", cam->far_clip,
                       cam->near_clip);
  if (s == SATF_OK)
    s = parse_camera_keys(ctx, obj, cam);
done:
  scene_pop(ctx, previous);
  return s;
}

/* Reads a light's color, intensity and direction (normalized) or position
 * from obj, the light's type already in light; missing values come from
 * def, or the documented defaults when def is NULL (direction/position
 * then required). */
static satf_status parse_light_values(scene_ctx *ctx, const cJSON *obj,
                                      const satf_scene_light *def,
                                      satf_scene_light *light) {
  const scene_field *color = scene_field_find(&SCENE_LIGHT, "color"),
                    *intensity = scene_field_find(&SCENE_LIGHT, "intensity");
  satf_status s;
  if ((s = scene_key_vec(ctx, obj, color->key, 3, &color->range,
                         def ? def->color : color->def3, light->color)) !=
          SATF_OK ||
      (s = scene_key_float(ctx, obj, intensity->key, &intensity->range,
                           def ? def->intensity : intensity->def,
                           &light->intensity)) != SATF_OK)
    return s;
  if (light->type == SATF_SCENE_LIGHT_POINT)
    return scene_key_vec(ctx, obj, "position", 3, &R_COORD,
                         def ? def->position : NULL, light->position);
  if ((s = scene_key_vec(ctx, obj, "direction", 3, &R_COORD,
                         def ? def->direction : NULL, light->direction)) !=
      SATF_OK)
    return s;
  double len;
  if ((s = scene_check_direction(ctx, light->direction, &len)) != SATF_OK)
    return s;
  scene_normalize(light->direction, len);
  return SATF_OK;
}

/* A light key over the static light `user`: its direction or position,
 * color and intensity. */
static satf_status read_light_key(scene_ctx *ctx, const cJSON *e, void *out,
                                  const void *user) {
  static const char *const dir_keys[] = {"frame", "direction", "color",
                                         "intensity", NULL};
  static const char *const point_keys[] = {"frame", "position", "color",
                                           "intensity", NULL};
  static const char *const fixed[] = {"type", NULL};
  const satf_scene_light *light = user;
  scene_light_key *key = out;
  int point = light->type == SATF_SCENE_LIGHT_POINT;
  satf_scene_light tmp = *light;
  satf_status s;
  if ((s = scene_check_keys(ctx, e, point ? point_keys : dir_keys)) !=
          SATF_OK ||
      (s = scene_tracks_reject_fixed(ctx, e, fixed,
                                     "a light key may give its direction or "
                                     "position, color and intensity")) !=
          SATF_OK ||
      (s = parse_light_values(ctx, e, light, &tmp)) != SATF_OK)
    return s;
  const char *vector = point ? "position" : "direction";
  if (!point && !cJSON_GetObjectItemCaseSensitive(e, vector))
    memcpy(tmp.direction, light->direction, sizeof tmp.direction);
  memcpy(key->vector, point ? tmp.position : tmp.direction, sizeof key->vector);
  memcpy(key->color, tmp.color, sizeof key->color);
  key->intensity = tmp.intensity;
  if (cJSON_GetObjectItemCaseSensitive(e, vector))
    key->given |= SCENE_GIVES_VECTOR;
  if (cJSON_GetObjectItemCaseSensitive(e, "color"))
    key->given |= SCENE_GIVES_COLOR;
  if (cJSON_GetObjectItemCaseSensitive(e, "intensity"))
    key->given |= SCENE_GIVES_INTENSITY;
  return SATF_OK;
}

static satf_status parse_light_keys(scene_ctx *ctx, const cJSON *obj, int index,
                                    const satf_scene_light *light) {
  scene_track scratch = {0}, *t = &scratch;
  if (scene_tracks_has_keys(ctx, obj)) {
    t = scene_anim_light_tracks(ctx->scene->animation, ctx->scene->n_lights);
    if (!t)
      return scene_nomem(ctx);
    t += index;
  }
  return scene_tracks_read(ctx, obj, sizeof(scene_light_key), read_light_key,
                           light, t);
}

static satf_status parse_light(scene_ctx *ctx, const cJSON *obj, int index,
                               satf_scene_light *light) {
  static const char *const types[] = {"directional", "point"};
  static const char *const dir_keys[] = {"type",      "direction", "color",
                                         "intensity", "keys",      NULL};
  static const char *const point_keys[] = {"type",      "position", "color",
                                           "intensity", "keys",     NULL};
  if (!cJSON_IsObject(obj))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(obj));
  int type;
  satf_status s = scene_key_enum(ctx, obj, "type", types, 2,
                                 SATF_SCENE_LIGHT_DIRECTIONAL, &type);
  if (s != SATF_OK)
    return s;
  light->type = (satf_scene_light_type)type;
  int point = light->type == SATF_SCENE_LIGHT_POINT;
  if ((s = scene_check_keys(ctx, obj, point ? point_keys : dir_keys)) !=
          SATF_OK ||
      (s = parse_light_values(ctx, obj, NULL, light)) != SATF_OK)
    return s;
  return parse_light_keys(ctx, obj, index, light);
}

static satf_status parse_lights(scene_ctx *ctx, const cJSON *root) {
  satf_scene *scene = ctx->scene;
  const cJSON *arr;
  int n;
  satf_status s = scene_key_array(ctx, root, "lights", 0, 1,
                                  SATF_SCENE_MAX_LIGHTS, &arr, &n);
  if (s != SATF_OK)
    return s;
  scene->lights = calloc(arr ? (size_t)n : 1, sizeof *scene->lights);
  if (!scene->lights)
    return scene_nomem(ctx);
  if (!arr) {
    /* A key light from the upper right, behind the default camera. */
    satf_scene_light *key = &scene->lights[0];
    const float from[3] = {0.4f, 0.5f, 0.75f};
    double len = scene_vec_length(from);
    key->type = SATF_SCENE_LIGHT_DIRECTIONAL;
    for (int k = 0; k < 3; k++) {
      key->direction[k] = (float)(-from[k] / len);
      key->color[k] = 1.0f;
    }
    key->intensity = 1.0f;
    scene->n_lights = 1;
    return SATF_OK;
  }
  scene->n_lights = n;
  size_t previous = scene_push_key(ctx, "lights");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    s = parse_light(ctx, e, i, &scene->lights[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_image(scene_ctx *ctx, const cJSON *root,
                               satf_scene_image *image) {
  static const cJSON empty = {0};
  const cJSON *obj;
  satf_status s = scene_key_object(ctx, root, "image", 0, &obj);
  if (s != SATF_OK)
    return s;
  if (!obj)
    obj = &empty;
  size_t previous = scene_push_key(ctx, "image");
  s = scene_fields_read(ctx, obj, &SCENE_IMAGE, image, NULL, NULL);
  scene_pop(ctx, previous);
  return s;
}

static satf_status parse_mesh(scene_ctx *ctx, const cJSON *obj,
                              const char *base_dir, satf_scene_mesh *mesh) {
  static const char *const keys[] = {"file", "color", "transform", NULL};
  if (!cJSON_IsObject(obj))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(obj));
  satf_status s;
  const cJSON *transform = NULL;
  if ((s = scene_check_keys(ctx, obj, keys)) != SATF_OK ||
      (s = scene_key_path(ctx, obj, "file", 1, base_dir, &mesh->file)) !=
          SATF_OK ||
      (s = scene_key_vec(ctx, obj, "color", 3, &R_UNIT, SKIN, mesh->color)) !=
          SATF_OK ||
      (s = scene_key_object(ctx, obj, "transform", 0, &transform)) != SATF_OK)
    return s;
  for (int k = 0; k < 16; k++)
    mesh->m[k] = k % 5 == 0 ? 1.0f : 0.0f;
  if (transform) {
    size_t previous = scene_push_key(ctx, "transform");
    s = scene_parse_transform(ctx, transform, mesh->m);
    scene_pop(ctx, previous);
  }
  return s;
}

static satf_status parse_meshes(scene_ctx *ctx, const cJSON *root,
                                const char *base_dir) {
  satf_scene *scene = ctx->scene;
  const cJSON *arr;
  int n;
  satf_status s = scene_key_array(ctx, root, "meshes", 0, 0,
                                  SATF_SCENE_MAX_MESHES, &arr, &n);
  if (s != SATF_OK || !arr || n == 0)
    return s;
  scene->meshes = calloc((size_t)n, sizeof *scene->meshes);
  if (!scene->meshes)
    return scene_nomem(ctx);
  scene->n_meshes = n;
  size_t previous = scene_push_key(ctx, "meshes");
  int i = 0;
  for (const cJSON *e = arr->child; e && s == SATF_OK; e = e->next, i++) {
    size_t inner = scene_push_index(ctx, i);
    s = parse_mesh(ctx, e, base_dir, &scene->meshes[i]);
    scene_pop(ctx, inner);
  }
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_parse_root(scene_ctx *ctx, const cJSON *root,
                             const char *base_dir) {
  static const char *const keys[] = {
      "description", "macro_clusters", "material", "effects", "camera",
      "lights",      "background",     "database", "image",   "animation",
      "meshes",      "strands",        NULL};
  satf_scene *scene = ctx->scene;
  if (!cJSON_IsObject(root))
    return scene_fail(ctx, SATF_ERR_FORMAT, "expected an object, got %s",
                      scene_type_name(root));
  satf_status s;
  if ((s = scene_check_keys(ctx, root, keys)) != SATF_OK ||
      (s = scene_key_copy(ctx, root, "description", 0, &scene->description)) !=
          SATF_OK ||
      (s = scene_tracks_parse_settings(ctx, root)) != SATF_OK ||
      (s = scene_parse_macro_clusters(ctx, root, base_dir)) != SATF_OK ||
      (s = parse_material(ctx, root, &scene->material)) != SATF_OK ||
      (s = parse_effects(ctx, root, &scene->effects)) != SATF_OK ||
      (s = parse_camera(ctx, root, &scene->camera)) != SATF_OK ||
      (s = parse_lights(ctx, root)) != SATF_OK ||
      (s = scene_key_vec(ctx, root, "background", 3, &R_UNIT, BACKGROUND,
                         scene->background)) != SATF_OK ||
      (s = scene_key_path(ctx, root, "database", 0, base_dir,
                          &scene->database)) != SATF_OK ||
      (s = scene_key_path(ctx, root, "strands", 0, base_dir,
                          &scene->strands_file)) != SATF_OK ||
      (s = parse_meshes(ctx, root, base_dir)) != SATF_OK)
    return s;
  return parse_image(ctx, root, &scene->image);
}

satf_status scene_parse_defaults(scene_ctx *ctx) {
  static const cJSON empty = {0};
  satf_scene *scene = ctx->scene;
  satf_status s;
  if ((s = parse_material(ctx, &empty, &scene->material)) != SATF_OK ||
      (s = parse_effects(ctx, &empty, &scene->effects)) != SATF_OK ||
      (s = parse_camera(ctx, &empty, &scene->camera)) != SATF_OK ||
      (s = parse_lights(ctx, &empty)) != SATF_OK)
    return s;
  memcpy(scene->background, BACKGROUND, sizeof scene->background);
  return parse_image(ctx, &empty, &scene->image);
}

void scene_parse_default_mesh(satf_scene_mesh *mesh) {
  memcpy(mesh->color, SKIN, sizeof mesh->color);
  for (int k = 0; k < 16; k++)
    mesh->m[k] = k % 5 == 0 ? 1.0f : 0.0f;
}
