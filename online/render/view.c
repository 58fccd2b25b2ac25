/* view.c - owns the view's maths (view.h): the camera and key light
 * projections, light vectors and colours, and the screen box of the scene
 * bounds. */
#include "view.h"

#include <math.h>
#include <string.h>

#include "mat4.h"
#include "satf/math.h"

void view_take(view *v, const satf_scene *scene) {
  v->camera = scene->camera;
  v->nlights = scene->n_lights < SATF_SCENE_MAX_LIGHTS ? scene->n_lights
                                                       : SATF_SCENE_MAX_LIGHTS;
  memcpy(v->lights, scene->lights,
         (size_t)v->nlights * sizeof(satf_scene_light));
  satf_scene_bounds(scene, v->lo, v->hi);
}

void view_grow(view *v, const float lo[3], const float hi[3]) {
  for (int a = 0; a < 3; a++) {
    v->lo[a] = lo[a] < v->lo[a] ? lo[a] : v->lo[a];
    v->hi[a] = hi[a] > v->hi[a] ? hi[a] : v->hi[a];
  }
}

void view_light_vector(const satf_scene_light *l, float out[4]) {
  if (l->type == SATF_SCENE_LIGHT_POINT) {
    memcpy(out, l->position, 3 * sizeof(float));
    out[3] = 1.0f;
  } else {
    out[0] = -l->direction[0];
    out[1] = -l->direction[1];
    out[2] = -l->direction[2];
    out[3] = 0.0f;
  }
}

void view_light_local(const float inv[16], const satf_scene_light *l,
                      float out[4]) {
  float lv[4];
  view_light_vector(l, lv);
  if (lv[3] != 0.0f)
    satf_mat4_point(inv, lv, out);
  else
    satf_mat4_vector(inv, lv, out);
  out[3] = lv[3];
}

void view_light_colors(const view *v, float *col) {
  for (int k = 0; k < v->nlights; k++)
    for (int a = 0; a < 3; a++)
      col[3 * k + a] = v->lights[k].color[a] * v->lights[k].intensity;
}

float view_radius(const view *v, float centre[3]) {
  float d2 = 0.0f;
  for (int a = 0; a < 3; a++) {
    centre[a] = 0.5f * (v->lo[a] + v->hi[a]);
    float h = 0.5f * (v->hi[a] - v->lo[a]);
    d2 += h * h;
  }
  return sqrtf(d2) + 1e-3f;
}

/* Distance squared between two points. */
static float distance2(const float a[3], const float b[3]) {
  float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return satf_dot3f(d, d);
}

/* A point light is treated as directional from its position towards the
 * scene centre. */
void view_light_map(const view *v, int light, float viewproj[16],
                    float *radius) {
  float c[3], rad = view_radius(v, c), lv[4], dir[3];
  view_light_vector(&v->lights[light], lv);
  for (int a = 0; a < 3; a++)
    dir[a] = lv[3] != 0.0f ? lv[a] - c[a] : lv[a];
  if (!(satf_normalize3f(dir) > 0)) {
    dir[0] = dir[2] = 0.0f;
    dir[1] = 1.0f;
  }
  float eye[3] = {c[0] + 2 * rad * dir[0], c[1] + 2 * rad * dir[1],
                  c[2] + 2 * rad * dir[2]};
  float up[3] = {0, 1, 0};
  if (fabsf(dir[1]) > 0.95f) {
    up[1] = 0;
    up[2] = 1;
  }
  float look[16], proj[16];
  satf_mat4_look_at(eye, c, up, look);
  satf_mat4_ortho(-rad, rad, -rad, rad, rad, 3 * rad, proj);
  satf_mat4_mul(proj, look, viewproj);
  *radius = rad;
}

void view_matrices(const view *v, float look[16], float proj[16]) {
  const satf_scene_camera *cam = &v->camera;
  float c[3], rad = view_radius(v, c);
  float n = cam->near_clip, f = cam->far_clip;
  if (!(n > 0.0f && f > n)) {
    float d = sqrtf(distance2(cam->position, c));
    f = d + 1.5f * rad;
    n = d - 1.5f * rad;
    if (n < 0.002f * f)
      n = 0.002f * f;
  }
  satf_mat4_look_at(cam->position, cam->target, cam->up, look);
  satf_mat4_perspective(cam->fov_y, (float)v->width / (float)v->height, n, f,
                        proj);
}

void view_camera(const view *v, float viewproj[16]) {
  float look[16], proj[16];
  view_matrices(v, look, proj);
  /* the anti-aliasing sample's sub-pixel offset (samples.c), as a shift of
   * normalised device coordinates: x_ndc += 2 dx / width */
  float dx = 2.0f * v->jitter[0] / (float)v->width;
  float dy = 2.0f * v->jitter[1] / (float)v->height;
  for (int k = 0; k < 4; k++) {
    proj[k] += dx * proj[12 + k];
    proj[4 + k] += dy * proj[12 + k];
  }
  satf_mat4_mul(proj, look, viewproj);
}

void view_screen_box(const view *v, const float viewproj[16], int box[4]) {
  float mn[2] = {1e30f, 1e30f}, mx[2] = {-1e30f, -1e30f};
  int behind = 0;
  for (int c = 0; c < 8; c++) {
    float p[3] = {c & 1 ? v->hi[0] : v->lo[0], c & 2 ? v->hi[1] : v->lo[1],
                  c & 4 ? v->hi[2] : v->lo[2]};
    float w = viewproj[12] * p[0] + viewproj[13] * p[1] + viewproj[14] * p[2] +
              viewproj[15];
    if (w <= 1e-6f) {
      behind = 1;
      break;
    }
    for (int a = 0; a < 2; a++) {
      float q = (viewproj[4 * a] * p[0] + viewproj[4 * a + 1] * p[1] +
                 viewproj[4 * a + 2] * p[2] + viewproj[4 * a + 3]) /
                w;
      mn[a] = q < mn[a] ? q : mn[a];
      mx[a] = q > mx[a] ? q : mx[a];
    }
  }
  int size[2] = {v->width, v->height};
  for (int a = 0; a < 2; a++) {
    int lo = behind ? 0 : (int)floorf((mn[a] * 0.5f + 0.5f) * size[a]) - 1;
    int hi = behind ? size[a] : (int)ceilf((mx[a] * 0.5f + 0.5f) * size[a]) + 1;
    lo = lo < 0 ? 0 : lo > size[a] ? size[a] : lo;
    hi = hi < lo ? lo : hi > size[a] ? size[a] : hi;
    box[a] = lo;
    box[2 + a] = hi - lo;
  }
}
