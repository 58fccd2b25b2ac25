/* bench_turn.h - the turning camera of the frame benchmarks (bench_frames,
 * bench_lookup turn): every view azimuth changes each frame. */
#ifndef SATF_TESTS_BENCH_TURN_H
#define SATF_TESTS_BENCH_TURN_H

#include <math.h>

#include "satf/math.h"
#include "satf/scene.h"

/* Turns the camera about its up axis through the target. */
static inline void bench_turn(satf_scene_camera *cam, float angle) {
  float v[3], kx[3];
  for (int a = 0; a < 3; a++)
    v[a] = cam->position[a] - cam->target[a];
  float c = cosf(angle), s = sinf(angle), kv = satf_dot3f(cam->up, v);
  satf_cross3f(cam->up, v, kx);
  for (int a = 0; a < 3; a++)
    cam->position[a] =
        cam->target[a] + v[a] * c + kx[a] * s + cam->up[a] * kv * (1 - c);
}

#endif
