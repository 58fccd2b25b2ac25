/* scene_report.h - where the scene reader is and what it says: the key path
 * of the value being read ("a.b[2].c"), errors and warnings that name it
 * ("NAME: a.b[2].c: what is wrong"), and the warning list of the scene being
 * built. Used by the parser and by snapshots; knows no JSON and no schema.
 *
 * The private headers of the scene library form one chain without cycles
 * (online/scene/README.md): report -> values -> tracks -> parse_instance ->
 * parse_cluster -> parse -> load; anim, check, interp and transform are
 * leaves the others share. */
#ifndef SATF_ONLINE_SCENE_REPORT_H
#define SATF_ONLINE_SCENE_REPORT_H

#include <stddef.h>

#include "satf/satf.h"
#include "satf/scene.h"

#define SCENE_PATH_MAX 512
#define SCENE_WARNINGS_KEPT 256

typedef struct scene_ctx {
  const char *name;          /* prefixes every message */
  char path[SCENE_PATH_MAX]; /* key path of the value being read */
  size_t len;
  satf_error *err;
  satf_scene *scene;    /* receives warnings */
  int warnings_dropped; /* beyond SCENE_WARNINGS_KEPT */
} scene_ctx;

/* Appends ".key" (or "key" at the root) / "[index]"; returns the previous
 * length for scene_pop. */
size_t scene_push_key(scene_ctx *ctx, const char *key);
size_t scene_push_index(scene_ctx *ctx, int index);
void scene_pop(scene_ctx *ctx, size_t previous);

/* Fails with "NAME: PATH: message" (PATH of the current value). */
satf_status scene_fail(scene_ctx *ctx, satf_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Same for the child `key` of the current value. */
satf_status scene_fail_key(scene_ctx *ctx, const char *key, satf_status status,
                           const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
satf_status scene_nomem(scene_ctx *ctx);
/* Records "NAME: PATH: message" as a warning; fails only on NOMEM. */
satf_status scene_warn(scene_ctx *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Adds "N more warnings not shown" when warnings were dropped. */
satf_status scene_warn_dropped(scene_ctx *ctx);

/* Escapes and shortens text from the file for a message. */
const char *scene_quote(const char *text, char *buf, size_t size);

#endif
