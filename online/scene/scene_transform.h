/* scene_transform.h - the affine instance transforms of macro-clusters
 * (SATF sec. 3.1: clusters of a macro-cluster are "derived from each other
 * via simple transformations"): composing translate/rotate/scale into a
 * row-major 4x4 matrix and checking that a matrix is usable. */
#ifndef SATF_ONLINE_SCENE_TRANSFORM_H
#define SATF_ONLINE_SCENE_TRANSFORM_H

void scene_matrix_identity(float m[16]);

/* m = T(translate) * R(axis, angle) * S(scale): a point is scaled first,
 * then rotated about the unit axis by angle_rad (right-handed), then
 * translated. */
void scene_matrix_trs(const double translate[3], const double axis[3],
                      double angle_rad, const double scale[3], float m[16]);

/* Determinant of the upper-left 3x3 block. */
double scene_matrix_det3(const float m[16]);

/* Largest deviation of the bottom row from (0, 0, 0, 1). */
double scene_matrix_projective_error(const float m[16]);

#endif
