/* math.h - the one small vector and constants header of satf (part of the
 * common library; header only). Every file that needs pi or a 3-vector
 * helper takes it from here, in double (d) or float (f) precision, so the
 * same formula is written once. */
#ifndef SATF_MATH_H
#define SATF_MATH_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SATF_PI 3.14159265358979323846
#define SATF_TWO_PI (2.0 * SATF_PI)
#define SATF_PI_F ((float)SATF_PI)
#define SATF_TWO_PI_F ((float)SATF_TWO_PI)

static inline double satf_dot3d(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline float satf_dot3f(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* out = a x b; out may alias a or b. */
static inline void satf_cross3d(const double a[3], const double b[3],
                                double out[3]) {
  double x = a[1] * b[2] - a[2] * b[1];
  double y = a[2] * b[0] - a[0] * b[2];
  double z = a[0] * b[1] - a[1] * b[0];
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

static inline void satf_cross3f(const float a[3], const float b[3],
                                float out[3]) {
  float x = a[1] * b[2] - a[2] * b[1];
  float y = a[2] * b[0] - a[0] * b[2];
  float z = a[0] * b[1] - a[1] * b[0];
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

/* Normalises v in place (a zero vector stays zero); returns its former
 * length. */
static inline double satf_normalize3d(double v[3]) {
  double len = sqrt(satf_dot3d(v, v));
  if (len > 0.0) {
    v[0] /= len;
    v[1] /= len;
    v[2] /= len;
  }
  return len;
}

static inline float satf_normalize3f(float v[3]) {
  float len = sqrtf(satf_dot3f(v, v));
  if (len > 0.0f) {
    v[0] /= len;
    v[1] /= len;
    v[2] /= len;
  }
  return len;
}

/* Squared distance from p to the segment a-b (its nearest point clamped to
 * the ends; a degenerate segment is the point a). */
static inline float satf_segment_dist2f(const float p[3], const float a[3],
                                        const float b[3]) {
  float ab[3], ap[3], d2 = 0.0f, f = 0.0f;
  for (int c = 0; c < 3; c++) {
    ab[c] = b[c] - a[c];
    ap[c] = p[c] - a[c];
    d2 += ab[c] * ab[c];
    f += ap[c] * ab[c];
  }
  f = d2 > 0.0f ? fminf(fmaxf(f / d2, 0.0f), 1.0f) : 0.0f;
  float e2 = 0.0f;
  for (int c = 0; c < 3; c++) {
    float e = ap[c] - f * ab[c];
    e2 += e * e;
  }
  return e2;
}

#ifdef __cplusplus
}
#endif
#endif
