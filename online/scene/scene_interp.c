/* scene_interp.c - key interpolation: cubic Hermite with Catmull-Rom
 * tangents, quaternion slerp and the polar decomposition of key matrices. */
#include "scene_interp.h"

#include <math.h>

static void add_term(scene_weights *w, int key, double weight) {
  w->key[w->n_terms] = key;
  w->w[w->n_terms] = weight;
  w->n_terms++;
}

/* The cubic Hermite basis on u in [0, 1]: h00, h10, h01, h11 weight the
 * start value, start tangent, end value and end tangent. */
static void hermite_basis(double u, double h[4]) {
  double u2 = u * u, u3 = u2 * u;
  h[0] = 2.0 * u3 - 3.0 * u2 + 1.0;
  h[1] = u3 - 2.0 * u2 + u;
  h[2] = -2.0 * u3 + 3.0 * u2;
  h[3] = u3 - u2;
}

void scene_interp_weights(const double *t, int n, double frame,
                          scene_weights *w) {
  w->n_terms = 0;
  w->u = 0.0;
  if (n <= 1 || !(frame > t[0])) {
    w->base = w->next = 0;
    return;
  }
  if (frame >= t[n - 1]) {
    w->base = w->next = n - 1;
    return;
  }
  int lo = 0, hi = n - 1; /* t[lo] <= frame < t[hi] */
  while (hi - lo > 1) {
    int mid = lo + (hi - lo) / 2;
    if (t[mid] <= frame)
      lo = mid;
    else
      hi = mid;
  }
  w->base = w->next = lo;
  if (frame == t[lo])
    return;
  int i = lo, j = lo + 1;
  double h = t[j] - t[i], u = (frame - t[i]) / h, b[4];
  hermite_basis(u, b);
  w->next = j;
  w->u = u;
  /* Tangents (per frame) are centred differences over the neighbouring
   * keys, one-sided at the ends; both segments meeting at a key use the
   * same tangent there, hence C1. Written against differences d_k = v_k -
   * v_i: v = v_i + h01 d_j + h10 h m_i + h11 h m_j. */
  double wj = b[2];
  if (i > 0) {
    double c = h * b[1] / (t[j] - t[i - 1]); /* m_i = (d_j - d_{i-1}) / .. */
    wj += c;
    add_term(w, i - 1, -c);
  } else {
    wj += b[1]; /* m_i = d_j / h */
  }
  if (j + 1 < n)
    add_term(w, j + 1, h * b[3] / (t[j + 1] - t[i])); /* m_j = d_{j+1} / .. */
  else
    wj += b[3]; /* m_j = d_j / h */
  add_term(w, j, wj);
}

void scene_interp_blend(const scene_weights *w, const float *const values[4],
                        int count, float *out) {
  for (int e = 0; e < count; e++) {
    double base = values[0][e], v = base;
    for (int i = 0; i < w->n_terms; i++)
      v += w->w[i] * ((double)values[1 + i][e] - base);
    out[e] = (float)v;
  }
}

static void quat_normalize(double q[4]) {
  double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(len > 0.0)) {
    q[0] = 1.0, q[1] = q[2] = q[3] = 0.0;
    return;
  }
  for (int k = 0; k < 4; k++)
    q[k] /= len;
}

void scene_quat_from_axis_angle(const double axis[3], double angle_rad,
                                double q[4]) {
  double s = sin(0.5 * angle_rad);
  q[0] = cos(0.5 * angle_rad);
  q[1] = axis[0] * s;
  q[2] = axis[1] * s;
  q[3] = axis[2] * s;
}

void scene_quat_from_matrix(const double r[9], double q[4]) {
  /* Shepperd's method: divide by the largest of the four candidates. */
  double trace = r[0] + r[4] + r[8];
  if (trace > 0.0) {
    double s = 2.0 * sqrt(trace + 1.0);
    q[0] = 0.25 * s;
    q[1] = (r[7] - r[5]) / s;
    q[2] = (r[2] - r[6]) / s;
    q[3] = (r[3] - r[1]) / s;
  } else if (r[0] > r[4] && r[0] > r[8]) {
    double s = 2.0 * sqrt(1.0 + r[0] - r[4] - r[8]);
    q[0] = (r[7] - r[5]) / s;
    q[1] = 0.25 * s;
    q[2] = (r[1] + r[3]) / s;
    q[3] = (r[2] + r[6]) / s;
  } else if (r[4] > r[8]) {
    double s = 2.0 * sqrt(1.0 + r[4] - r[0] - r[8]);
    q[0] = (r[2] - r[6]) / s;
    q[1] = (r[1] + r[3]) / s;
    q[2] = 0.25 * s;
    q[3] = (r[5] + r[7]) / s;
  } else {
    double s = 2.0 * sqrt(1.0 + r[8] - r[0] - r[4]);
    q[0] = (r[3] - r[1]) / s;
    q[1] = (r[2] + r[6]) / s;
    q[2] = (r[5] + r[7]) / s;
    q[3] = 0.25 * s;
  }
  quat_normalize(q);
}

void scene_quat_to_matrix(const double q[4], double r[9]) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  r[0] = 1.0 - 2.0 * (y * y + z * z);
  r[1] = 2.0 * (x * y - w * z);
  r[2] = 2.0 * (x * z + w * y);
  r[3] = 2.0 * (x * y + w * z);
  r[4] = 1.0 - 2.0 * (x * x + z * z);
  r[5] = 2.0 * (y * z - w * x);
  r[6] = 2.0 * (x * z - w * y);
  r[7] = 2.0 * (y * z + w * x);
  r[8] = 1.0 - 2.0 * (x * x + y * y);
}

void scene_quat_slerp(const double a[4], const double b[4], double u,
                      double out[4]) {
  double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  double sign = 1.0;
  if (c < 0.0) /* q and -q are one rotation: take the shorter arc */
    c = -c, sign = -1.0;
  double wa, wb;
  if (c > 0.9999995) {
    wa = 1.0 - u, wb = u; /* nearly parallel: lerp, then normalize */
  } else {
    double theta = acos(c), s = sin(theta);
    wa = sin((1.0 - u) * theta) / s;
    wb = sin(u * theta) / s;
  }
  for (int k = 0; k < 4; k++)
    out[k] = wa * a[k] + sign * wb * b[k];
  quat_normalize(out);
}

static double det3(const double m[9]) {
  return m[0] * (m[4] * m[8] - m[5] * m[7]) -
         m[1] * (m[3] * m[8] - m[5] * m[6]) +
         m[2] * (m[3] * m[7] - m[4] * m[6]);
}

/* inverse transpose of m, given its non-zero determinant */
static void inverse_transpose(const double m[9], double det, double out[9]) {
  out[0] = (m[4] * m[8] - m[5] * m[7]) / det;
  out[1] = (m[5] * m[6] - m[3] * m[8]) / det;
  out[2] = (m[3] * m[7] - m[4] * m[6]) / det;
  out[3] = (m[2] * m[7] - m[1] * m[8]) / det;
  out[4] = (m[0] * m[8] - m[2] * m[6]) / det;
  out[5] = (m[1] * m[6] - m[0] * m[7]) / det;
  out[6] = (m[1] * m[5] - m[2] * m[4]) / det;
  out[7] = (m[2] * m[3] - m[0] * m[5]) / det;
  out[8] = (m[0] * m[4] - m[1] * m[3]) / det;
}

void scene_polar_decompose(const double m[9], double r[9], double s[9]) {
  /* Newton's iteration X <- (g X + X^-T / g) / 2 with determinant scaling
   * g = |det X|^(-1/3) converges to the orthogonal polar factor (Higham
   * 1986); starting from sign(det m) m makes that factor a rotation. */
  double x[9], inv_t[9];
  double sign = det3(m) < 0.0 ? -1.0 : 1.0;
  for (int k = 0; k < 9; k++)
    x[k] = sign * m[k];
  for (int it = 0; it < 100; it++) {
    double det = det3(x);
    if (!(fabs(det) > 0.0) || !isfinite(det))
      break;
    double g = pow(fabs(det), -1.0 / 3.0), change = 0.0, size = 0.0;
    inverse_transpose(x, det, inv_t);
    for (int k = 0; k < 9; k++) {
      double next = 0.5 * (g * x[k] + inv_t[k] / g);
      change += fabs(next - x[k]);
      size += fabs(next);
      x[k] = next;
    }
    if (change <= 1e-14 * size)
      break;
  }
  /* Through a unit quaternion so that r is exactly orthonormal. */
  double q[4];
  scene_quat_from_matrix(x, q);
  scene_quat_to_matrix(q, r);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      s[3 * i + j] = r[i] * m[j] + r[3 + i] * m[3 + j] + r[6 + i] * m[6 + j];
}
