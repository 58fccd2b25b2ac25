/* scene_parse_cluster.h - the hair hierarchy of the scene schema:
 * macro-clusters, their prototype clusters with keys, shells and densities,
 * and (through scene_parse_instance.h) their instances. */
#ifndef SATF_ONLINE_SCENE_PARSE_CLUSTER_H
#define SATF_ONLINE_SCENE_PARSE_CLUSTER_H

#include "scene_parse_instance.h"

/* Reads root.macro_clusters into ctx->scene, enforcing the scene-wide
 * cluster and HSV limits before allocating instances. base_dir (may be
 * NULL) is prefixed to relative VDB paths. */
satf_status scene_parse_macro_clusters(scene_ctx *ctx, const cJSON *root,
                                       const char *base_dir);

#endif
