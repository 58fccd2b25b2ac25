/* mat4.h - the 4x4 matrix arithmetic of the renderer. Matrices are
 * row-major float[16] (m[4 * row + col]), as in scene files; upload them to
 * GL with transpose = GL_TRUE. */
#ifndef SATF_ONLINE_MAT4_H
#define SATF_ONLINE_MAT4_H

void satf_mat4_identity(float m[16]);
void satf_mat4_mul(const float a[16], const float b[16], float out[16]);
/* General inverse; returns 0 when the matrix is singular. */
int satf_mat4_invert(const float m[16], float out[16]);
void satf_mat4_point(const float m[16], const float p[3], float out[3]);
void satf_mat4_vector(const float m[16], const float v[3], float out[3]);
/* Right-handed view matrix looking from eye at target. */
void satf_mat4_look_at(const float eye[3], const float target[3],
                       const float up[3], float out[16]);
/* OpenGL clip space (z in [-1, 1]). */
void satf_mat4_perspective(float fov_y_deg, float aspect, float near_clip,
                           float far_clip, float out[16]);
void satf_mat4_ortho(float l, float r, float b, float t, float n, float f,
                     float out[16]);
/* Determinant of the upper 3x3 (negative for a mirror). */
float satf_mat4_det3(const float m[16]);
/* How far the upper 3x3 is from a similarity (rotation, mirror, uniform
 * scale): max |c_i . c_j - L delta_ij| / L over its columns c, L their mean
 * squared length; 0 for a similarity. The lengths of the columns go to
 * len. */
float satf_mat4_similarity_error(const float m[16], float len[3]);
/* The inverse-transpose of the upper 3x3, for normals (row-major 3x3). */
void satf_mat4_normal_matrix(const float m[16], float out[9]);

#endif
