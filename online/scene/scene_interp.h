/* scene_interp.h - interpolation between animation keys (samples/README.md,
 * "Animation"): C1 cubic Hermite weights with Catmull-Rom tangents on
 * non-uniformly spaced key frames, and rotations as unit quaternions (slerp,
 * polar decomposition of a key's matrix). Knows nothing about JSON or the
 * scene; all arithmetic is in double. */
#ifndef SATF_ONLINE_SCENE_INTERP_H
#define SATF_ONLINE_SCENE_INTERP_H

/* How a value at one frame follows from the keys around it:
 *   v = v[base] + sum_i w[i] * (v[key[i]] - v[base]).
 * Written as differences from the base key so that a frame on a key, or
 * keys that all hold one value, reproduce that value bit for bit. */
typedef struct scene_weights {
  int base;    /* the key at or before the frame (the first one before it) */
  int next;    /* base + 1 between keys; base on a key or outside them */
  double u;    /* position in [base, next], 0 on a key or outside */
  int n_terms; /* 0 on a key or outside the keys (held) */
  int key[3];
  double w[3];
} scene_weights;

/* Weights at `frame` for n >= 1 strictly increasing key frames. Outside
 * [frames[0], frames[n-1]] the end key is held. */
void scene_interp_weights(const double *frames, int n, double frame,
                          scene_weights *w);

/* out[e] = blend of values[0] (the base key's array) and values[1 + i]
 * (the array of key w->key[i]) for e < count. out may alias none of them. */
void scene_interp_blend(const scene_weights *w, const float *const values[4],
                        int count, float *out);

/* Unit quaternions are (w, x, y, z). */
void scene_quat_from_axis_angle(const double axis[3], double angle_rad,
                                double q[4]);
void scene_quat_from_matrix(const double r[9], double q[4]);
void scene_quat_to_matrix(const double q[4], double r[9]);
/* Shortest-arc spherical interpolation, u in [0, 1]. */
void scene_quat_slerp(const double a[4], const double b[4], double u,
                      double out[4]);

/* m = r * s with r a rotation (det +1) and s = r^T m symmetric (a stretch,
 * negated when det m < 0). 3x3 row-major. */
void scene_polar_decompose(const double m[9], double r[9], double s[9]);

#endif
