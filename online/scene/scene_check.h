/* scene_check.h - the checks a scene value must pass wherever it comes
 * from, shared by the parser (values read from the file) and snapshots
 * (values interpolated between keys): a trajectory with a length, a camera
 * that looks somewhere, a light direction that is not zero, and the one
 * normalization both use so that their results agree bit for bit. */
#ifndef SATF_ONLINE_SCENE_CHECK_H
#define SATF_ONLINE_SCENE_CHECK_H

#include "scene_report.h"

double scene_vec_length(const float v[3]);

/* v[k] = (float)(v[k] / len): how the parser makes a direction or an up
 * vector of length len a unit one. */
void scene_normalize(float v[3], double len);

/* Largest distance of a trajectory's control points from its first one
 * (3 * n floats); a trajectory needs one above 1e-6. */
double scene_trajectory_extent(const float *trajectory, int n);

/* Checks that cam looks somewhere (target != position) with an up vector
 * off the view direction, and normalizes up; errors name "target" or "up"
 * under the ctx path. */
satf_status scene_check_camera_view(scene_ctx *ctx, satf_scene_camera *cam);

/* The length of a light direction; fails with "direction: has zero length"
 * under the ctx path when it has none. */
satf_status scene_check_direction(scene_ctx *ctx, const float v[3],
                                  double *len);

#endif
