/* scene_parse_instance.h - transforms in the scene schema: the instances of
 * a macro-cluster with their keys, and the static transforms of meshes. */
#ifndef SATF_ONLINE_SCENE_PARSE_INSTANCE_H
#define SATF_ONLINE_SCENE_PARSE_INSTANCE_H

#include "scene_tracks.h"

/* instances[instance] of macro_clusters[macro_cluster] (item; the ctx path
 * is the instance's), with its keys. */
satf_status scene_parse_instance(scene_ctx *ctx, const cJSON *item,
                                 int macro_cluster, int instance,
                                 satf_scene_instance *out);

/* A static transform object (matrix, or translate/rotate/scale) as in
 * instances, without keys. */
satf_status scene_parse_transform(scene_ctx *ctx, const cJSON *item,
                                  float m[16]);

#endif
