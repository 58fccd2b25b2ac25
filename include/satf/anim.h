/* anim.h - keyframe animation of a scene (samples/README.md, "Animation";
 * SATF Fig. 8): the frame range and rate of an animated scene, static
 * snapshots of it at any frame, and cheap comparisons that tell a renderer
 * what changed between two snapshots.
 *
 * An animated scene is an ordinary satf_scene whose fields hold the static
 * values (the defaults of every key) plus keyframes that only this API
 * reads. A snapshot is a complete static satf_scene with every animated
 * value interpolated; render it as any loaded scene and free it with
 * satf_scene_destroy. */
#ifndef SATF_ANIM_H
#define SATF_ANIM_H

#include "satf/satf.h"
#include "satf/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 when the scene file had an "animation" object (even with no keys). */
int satf_scene_is_animated(const satf_scene *scene);

/* The inclusive frame range; returns satf_scene_is_animated(scene). A
 * static scene gives 0 and 0. */
int satf_scene_frame_range(const satf_scene *scene, int *first, int *last);

/* Frames per second; 0 for a static scene. */
double satf_scene_fps(const satf_scene *scene);

/* A static copy of scene at `frame` (fractional frames interpolate too;
 * frames outside the keys hold the first or last key). Names, paths,
 * material, effects, image and every unanimated value are copied; the
 * snapshot has no warnings and satf_scene_is_animated(*out) == 0. A static
 * scene gives a plain copy. Fails (naming the scene, the object's key path
 * and the frame) on a non-finite frame or when interpolation produces an
 * unusable value: a trajectory whose points all coincide, a singular
 * instance transform, a camera looking along its up vector or at its own
 * position, or a zero light direction. */
satf_status satf_scene_at_frame(const satf_scene *scene, double frame,
                                satf_scene **out, satf_error *err);

/* 1 when macro_clusters[index].prototype has keys (its geometry may differ
 * between snapshots); 0 otherwise or for a bad index. */
int satf_scene_prototype_is_animated(const satf_scene *scene, int index);

/* 1 when instance j of macro_clusters[index] has keys. */
int satf_scene_instance_is_animated(const satf_scene *scene, int index,
                                    int instance);

/* Equality of what a renderer builds from: the cluster geometry
 * (trajectory, a, b, twist, shell and density parameters), the instance
 * transforms of a macro-cluster, the camera, one light. Bitwise on the
 * floats, so two snapshots taken where nothing moves compare equal. */
int satf_scene_prototype_equal(const satf_scene_cluster *a,
                               const satf_scene_cluster *b);
int satf_scene_instances_equal(const satf_scene_macro_cluster *a,
                               const satf_scene_macro_cluster *b);
int satf_scene_camera_equal(const satf_scene_camera *a,
                            const satf_scene_camera *b);
int satf_scene_light_equal(const satf_scene_light *a,
                           const satf_scene_light *b);

#ifdef __cplusplus
}
#endif
#endif
