/* scene_parse.h - the scene schema: fills a satf_scene from a parsed cJSON
 * tree, validating and defaulting every key (samples/README.md). The hair
 * hierarchy is scene_parse_cluster.h, the rest scene_parse.c. */
#ifndef SATF_ONLINE_SCENE_PARSE_H
#define SATF_ONLINE_SCENE_PARSE_H

#include "scene_parse_cluster.h"

/* Fills ctx->scene (already zeroed, name set) from root. base_dir (may be
 * NULL: paths are kept as written) is prefixed to relative paths. */
satf_status scene_parse_root(scene_ctx *ctx, const cJSON *root,
                             const char *base_dir);

/* Fills ctx->scene (zeroed, without macro-clusters) with what a file that
 * gives nothing but its hair would get: material, effects, an automatic
 * camera, the default key light, background and image size. */
satf_status scene_parse_defaults(scene_ctx *ctx);

/* A mesh's defaults: skin colour, identity transform. */
void scene_parse_default_mesh(satf_scene_mesh *mesh);

#endif
