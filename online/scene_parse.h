/* scene_parse.h - the scene schema: fills a satf_scene from a parsed cJSON
 * tree, validating and defaulting every key (samples/README.md). The hair
 * hierarchy lives in scene_cluster.c, the rest in scene_parse.c. */
#ifndef SATF_ONLINE_SCENE_PARSE_H
#define SATF_ONLINE_SCENE_PARSE_H

#include <cjson/cJSON.h>

#include "online/scene_json.h"

/* Fills ctx->scene (already zeroed, name set) from root. base_dir (may be
 * NULL: paths are kept as written) is prefixed to relative paths. */
satf_status scene_parse_root(scene_ctx *ctx, const cJSON *root,
                             const char *base_dir);

/* Reads root.macro_clusters into ctx->scene (scene_cluster.c), enforcing
 * the scene-wide cluster and HSV limits before allocating instances. */
satf_status scene_parse_macro_clusters(scene_ctx *ctx, const cJSON *root,
                                       const char *base_dir);

#endif
