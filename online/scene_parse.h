/* scene_parse.h - the scene schema: fills a satf_scene from a parsed cJSON
 * tree, validating and defaulting every key (samples/README.md). */
#ifndef SATF_ONLINE_SCENE_PARSE_H
#define SATF_ONLINE_SCENE_PARSE_H

#include <cjson/cJSON.h>

#include "online/scene_json.h"

/* Fills ctx->scene (already zeroed, name set) from root. base_dir (may be
 * NULL: paths are kept as written) is prefixed to relative paths. */
satf_status scene_parse_root(scene_ctx *ctx, const cJSON *root,
                             const char *base_dir);

/* base_dir + "/" + path for a relative path, a copy otherwise; NULL on
 * allocation failure. */
char *scene_resolve_path(const char *base_dir, const char *path);

#endif
