/* scene_check.c - checks shared by the parser and snapshots. */
#include "scene_check.h"

#include <math.h>

#include "satf/math.h"

double scene_vec_length(const float v[3]) {
  return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

void scene_normalize(float v[3], double len) {
  for (int k = 0; k < 3; k++)
    v[k] = (float)(v[k] / len);
}

double scene_trajectory_extent(const float *trajectory, int n) {
  double extent = 0.0;
  for (int p = 1; p < n; p++) {
    float d[3];
    for (int k = 0; k < 3; k++)
      d[k] = trajectory[3 * p + k] - trajectory[k];
    double len = scene_vec_length(d);
    if (len > extent)
      extent = len;
  }
  return extent;
}

satf_status scene_check_camera_view(scene_ctx *ctx, satf_scene_camera *cam) {
  float view[3];
  for (int k = 0; k < 3; k++)
    view[k] = cam->target[k] - cam->position[k];
  double view_len = scene_vec_length(view), up_len = scene_vec_length(cam->up);
  if (!(view_len > 1e-6))
    return scene_fail_key(ctx, "target", SATF_ERR_ARGUMENT,
                          "coincides with the camera position");
  float cross[3];
  satf_cross3f(view, cam->up, cross);
  if (!(up_len > 1e-9) || !(scene_vec_length(cross) > 1e-3 * view_len * up_len))
    return scene_fail_key(ctx, "up", SATF_ERR_ARGUMENT,
                          "is zero or parallel to the view direction");
  scene_normalize(cam->up, up_len);
  return SATF_OK;
}

satf_status scene_check_direction(scene_ctx *ctx, const float v[3],
                                  double *len) {
  *len = scene_vec_length(v);
  if (!(*len > 1e-9))
    return scene_fail_key(ctx, "direction", SATF_ERR_ARGUMENT,
                          "has zero length");
  return SATF_OK;
}

int satf_scene_normalize(float v[3]) {
  double len = scene_vec_length(v);
  if (!(len > 1e-9))
    return 0;
  scene_normalize(v, len);
  return 1;
}
