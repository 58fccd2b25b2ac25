/* scene_transform.c - instance transforms and world bounds. */
#include "scene_transform.h"

#include <float.h>
#include <math.h>

#include "satf/scene.h"

void scene_matrix_identity(float m[16]) {
  for (int i = 0; i < 16; i++)
    m[i] = (i % 5 == 0) ? 1.0f : 0.0f;
}

void scene_matrix_trs(const double translate[3], const double axis[3],
                      double angle_rad, const double scale[3], float m[16]) {
  /* Rodrigues: R = cos I + sin [k]x + (1 - cos) k k^T. */
  double c = cos(angle_rad), s = sin(angle_rad), C = 1.0 - c;
  double x = axis[0], y = axis[1], z = axis[2];
  double r[3][3] = {{c + x * x * C, x * y * C - z * s, x * z * C + y * s},
                    {y * x * C + z * s, c + y * y * C, y * z * C - x * s},
                    {z * x * C - y * s, z * y * C + x * s, c + z * z * C}};
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++)
      m[4 * i + j] = (float)(r[i][j] * scale[j]);
    m[4 * i + 3] = (float)translate[i];
  }
  m[12] = m[13] = m[14] = 0.0f;
  m[15] = 1.0f;
}

double scene_matrix_det3(const float m[16]) {
  return (double)m[0] * ((double)m[5] * m[10] - (double)m[6] * m[9]) -
         (double)m[1] * ((double)m[4] * m[10] - (double)m[6] * m[8]) +
         (double)m[2] * ((double)m[4] * m[9] - (double)m[5] * m[8]);
}

double scene_matrix_projective_error(const float m[16]) {
  double e = fabs(m[12]);
  if (fabs(m[13]) > e)
    e = fabs(m[13]);
  if (fabs(m[14]) > e)
    e = fabs(m[14]);
  if (fabs(m[15] - 1.0) > e)
    e = fabs(m[15] - 1.0);
  return e;
}

void satf_scene_instance_apply(const satf_scene_instance *instance,
                               const float p[3], float out[3]) {
  const float *m = instance->m;
  float x = p[0], y = p[1], z = p[2];
  for (int i = 0; i < 3; i++)
    out[i] = m[4 * i] * x + m[4 * i + 1] * y + m[4 * i + 2] * z + m[4 * i + 3];
}

static float curve_max(const satf_scene_curve *curve) {
  float r = 0.0f;
  for (int i = 0; i < curve->count; i++)
    if (curve->values[i] > r)
      r = curve->values[i];
  return r;
}

void satf_scene_bounds(const satf_scene *scene, float lo[3], float hi[3]) {
  for (int k = 0; k < 3; k++)
    lo[k] = FLT_MAX, hi[k] = -FLT_MAX;
  for (int i = 0; i < scene->n_macro_clusters; i++) {
    const satf_scene_cluster *c = &scene->macro_clusters[i].prototype;
    /* A B-spline stays in its control points' convex hull, and the swept
     * ellipse adds at most the largest half-axis around it. */
    float r = curve_max(&c->a);
    if (curve_max(&c->b) > r)
      r = curve_max(&c->b);
    float plo[3] = {FLT_MAX, FLT_MAX, FLT_MAX};
    float phi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (int p = 0; p < c->n_points; p++) {
      for (int k = 0; k < 3; k++) {
        float v = c->trajectory[3 * p + k];
        if (v - r < plo[k])
          plo[k] = v - r;
        if (v + r > phi[k])
          phi[k] = v + r;
      }
    }
    const satf_scene_macro_cluster *mc = &scene->macro_clusters[i];
    for (int j = 0; j < mc->n_instances; j++) {
      for (int corner = 0; corner < 8; corner++) {
        float p[3] = {(corner & 1) ? phi[0] : plo[0],
                      (corner & 2) ? phi[1] : plo[1],
                      (corner & 4) ? phi[2] : plo[2]};
        float w[3];
        satf_scene_instance_apply(&mc->instances[j], p, w);
        for (int k = 0; k < 3; k++) {
          if (w[k] < lo[k])
            lo[k] = w[k];
          if (w[k] > hi[k])
            hi[k] = w[k];
        }
      }
    }
  }
  if (lo[0] > hi[0]) /* no clusters */
    for (int k = 0; k < 3; k++)
      lo[k] = hi[k] = 0.0f;
}

void satf_scene_matrix_trs(const double translate[3], const double axis[3],
                           double angle_rad, const double scale[3],
                           float m[16]) {
  scene_matrix_trs(translate, axis, angle_rad, scale, m);
}
