/* mat4.c - see mat4.h. */
#include "mat4.h"

#include <math.h>
#include <string.h>

#include "satf/math.h"

void satf_mat4_identity(float m[16]) {
  memset(m, 0, 16 * sizeof(float));
  m[0] = m[5] = m[10] = m[15] = 1.0f;
}

void satf_mat4_mul(const float a[16], const float b[16], float out[16]) {
  float r[16];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      float s = 0.0f;
      for (int k = 0; k < 4; k++)
        s += a[4 * i + k] * b[4 * k + j];
      r[4 * i + j] = s;
    }
  memcpy(out, r, sizeof r);
}

int satf_mat4_invert(const float m[16], float out[16]) {
  /* Gauss-Jordan with partial pivoting, in double */
  double a[4][8];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 8; j++)
      a[i][j] = j < 4 ? m[4 * i + j] : (j - 4 == i);
  for (int c = 0; c < 4; c++) {
    int p = c;
    for (int r = c + 1; r < 4; r++)
      if (fabs(a[r][c]) > fabs(a[p][c]))
        p = r;
    if (fabs(a[p][c]) < 1e-12)
      return 0;
    for (int j = 0; j < 8; j++) {
      double t = a[c][j];
      a[c][j] = a[p][j];
      a[p][j] = t;
    }
    double inv = 1.0 / a[c][c];
    for (int j = 0; j < 8; j++)
      a[c][j] *= inv;
    for (int r = 0; r < 4; r++)
      if (r != c) {
        double f = a[r][c];
        for (int j = 0; j < 8; j++)
          a[r][j] -= f * a[c][j];
      }
  }
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      out[4 * i + j] = (float)a[i][j + 4];
  return 1;
}

void satf_mat4_point(const float m[16], const float p[3], float out[3]) {
  float r[3];
  for (int i = 0; i < 3; i++)
    r[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] +
           m[4 * i + 3];
  float w = m[12] * p[0] + m[13] * p[1] + m[14] * p[2] + m[15];
  for (int i = 0; i < 3; i++)
    out[i] = w != 0.0f && w != 1.0f ? r[i] / w : r[i];
}

void satf_mat4_vector(const float m[16], const float v[3], float out[3]) {
  float r[3];
  for (int i = 0; i < 3; i++)
    r[i] = m[4 * i] * v[0] + m[4 * i + 1] * v[1] + m[4 * i + 2] * v[2];
  memcpy(out, r, sizeof r);
}

void satf_mat4_look_at(const float eye[3], const float target[3],
                       const float up[3], float out[16]) {
  float f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
  satf_normalize3f(f);
  float s[3], u[3];
  satf_cross3f(f, up, s);
  satf_normalize3f(s);
  satf_cross3f(s, f, u);
  satf_mat4_identity(out);
  for (int j = 0; j < 3; j++) {
    out[j] = s[j];
    out[4 + j] = u[j];
    out[8 + j] = -f[j];
  }
  out[3] = -satf_dot3f(s, eye);
  out[7] = -satf_dot3f(u, eye);
  out[11] = satf_dot3f(f, eye);
}

void satf_mat4_perspective(float fov_y_deg, float aspect, float n, float f,
                           float out[16]) {
  float c = 1.0f / tanf(0.5f * fov_y_deg * SATF_PI_F / 180.0f);
  memset(out, 0, 16 * sizeof(float));
  out[0] = c / aspect;
  out[5] = c;
  out[10] = (f + n) / (n - f);
  out[11] = 2.0f * f * n / (n - f);
  out[14] = -1.0f;
}

void satf_mat4_ortho(float l, float r, float b, float t, float n, float f,
                     float out[16]) {
  satf_mat4_identity(out);
  out[0] = 2.0f / (r - l);
  out[5] = 2.0f / (t - b);
  out[10] = -2.0f / (f - n);
  out[3] = -(r + l) / (r - l);
  out[7] = -(t + b) / (t - b);
  out[11] = -(f + n) / (f - n);
}

void satf_mat4_normal_matrix(const float m[16], float out[9]) {
  float inv[16];
  if (!satf_mat4_invert(m, inv))
    satf_mat4_identity(inv);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      out[3 * i + j] = inv[4 * j + i];
}

float satf_mat4_det3(const float m[16]) {
  return m[0] * (m[5] * m[10] - m[6] * m[9]) -
         m[1] * (m[4] * m[10] - m[6] * m[8]) +
         m[2] * (m[4] * m[9] - m[5] * m[8]);
}

float satf_mat4_similarity_error(const float m[16], float len[3]) {
  double c[3][3], mean = 0.0, e = 0.0;
  for (int j = 0; j < 3; j++) {
    for (int i = 0; i < 3; i++)
      c[j][i] = m[4 * i + j];
    double l2 = c[j][0] * c[j][0] + c[j][1] * c[j][1] + c[j][2] * c[j][2];
    len[j] = (float)sqrt(l2);
    mean += l2 / 3.0;
  }
  if (!(mean > 0.0))
    return INFINITY;
  for (int a = 0; a < 3; a++)
    for (int b = a; b < 3; b++) {
      double d = c[a][0] * c[b][0] + c[a][1] * c[b][1] + c[a][2] * c[b][2];
      double dev = fabs(d - (a == b ? mean : 0.0)) / mean;
      e = dev > e ? dev : e;
    }
  return (float)e;
}
