/* scene_parse.h - the scene schema: fills a satf_scene from a parsed cJSON
 * tree, validating and defaulting every key (samples/README.md). The hair
 * hierarchy lives in scene_cluster.c and scene_instance.c, keyframes in
 * scene_anim_parse.c, the rest in scene_parse.c. The pieces shared with
 * the keyframe parser are declared here too. */
#ifndef SATF_ONLINE_SCENE_PARSE_H
#define SATF_ONLINE_SCENE_PARSE_H

#include <cjson/cJSON.h>

#include "scene_json.h"

/* Fills ctx->scene (already zeroed, name set) from root. base_dir (may be
 * NULL: paths are kept as written) is prefixed to relative paths. */
satf_status scene_parse_root(scene_ctx *ctx, const cJSON *root,
                             const char *base_dir);

/* Reads root.macro_clusters into ctx->scene (scene_cluster.c), enforcing
 * the scene-wide cluster and HSV limits before allocating instances. */
satf_status scene_parse_macro_clusters(scene_ctx *ctx, const cJSON *root,
                                       const char *base_dir);

/* The `trajectory` of obj into c (allocated; 2..4096 points in range, not
 * all equal). */
satf_status scene_parse_trajectory(scene_ctx *ctx, const cJSON *obj,
                                   satf_scene_cluster *c);

/* A cluster curve obj[key], key "a", "b" or "twist", with that key's range;
 * out->values allocated. */
satf_status scene_parse_cluster_curve(scene_ctx *ctx, const cJSON *obj,
                                      const char *key, satf_scene_curve *out);

/* instances[instance] of macro_clusters[macro_cluster] (item; the ctx path
 * is the instance's), with its keys. */
/* A static transform object (matrix, or translate/rotate/scale) as in
 * instances, without keys. */
satf_status scene_parse_transform(scene_ctx *ctx, const cJSON *item,
                                  float m[16]);
/* The opaque meshes of the scene ("meshes"). */
satf_status scene_parse_meshes(scene_ctx *ctx, const cJSON *root,
                               const char *base_dir);

satf_status scene_parse_instance(scene_ctx *ctx, const cJSON *item,
                                 int macro_cluster, int instance,
                                 satf_scene_instance *out);

/* Checks that cam looks somewhere (target != position) with an up vector
 * off the view direction, and normalizes up; errors name "target" or "up"
 * under the ctx path. */
satf_status scene_check_camera_view(scene_ctx *ctx, satf_scene_camera *cam);

/* Reads a light's color, intensity and direction (normalized) or position
 * from obj, the light's type already in light; missing values come from
 * def, or the documented defaults when def is NULL (direction/position
 * then required). */
satf_status scene_parse_light_values(scene_ctx *ctx, const cJSON *obj,
                                     const satf_scene_light *def,
                                     satf_scene_light *light);

#endif
