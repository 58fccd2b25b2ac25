/* scene_report.c - the key path of the value being read, and the error and
 * warning messages that name it. */
#include "scene_report.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

size_t scene_push_key(scene_ctx *ctx, const char *key) {
  size_t previous = ctx->len;
  size_t room = sizeof ctx->path - ctx->len;
  int n =
      snprintf(ctx->path + ctx->len, room, "%s%s", ctx->len ? "." : "", key);
  ctx->len += (n < 0) ? 0 : ((size_t)n < room ? (size_t)n : room - 1);
  return previous;
}

size_t scene_push_index(scene_ctx *ctx, int index) {
  size_t previous = ctx->len;
  size_t room = sizeof ctx->path - ctx->len;
  int n = snprintf(ctx->path + ctx->len, room, "[%d]", index);
  ctx->len += (n < 0) ? 0 : ((size_t)n < room ? (size_t)n : room - 1);
  return previous;
}

void scene_pop(scene_ctx *ctx, size_t previous) {
  ctx->len = previous;
  ctx->path[previous] = '\0';
}

static const char *current_path(const scene_ctx *ctx) {
  return ctx->len ? ctx->path : "(root)";
}

static satf_status fail_v(scene_ctx *ctx, satf_status status, const char *fmt,
                          va_list ap) {
  char message[512];
  vsnprintf(message, sizeof message, fmt, ap);
  return satf_error_set(ctx->err, status, "%s: %s: %s", ctx->name,
                        current_path(ctx), message);
}

satf_status scene_fail(scene_ctx *ctx, satf_status status, const char *fmt,
                       ...) {
  va_list ap;
  va_start(ap, fmt);
  satf_status s = fail_v(ctx, status, fmt, ap);
  va_end(ap);
  return s;
}

satf_status scene_fail_key(scene_ctx *ctx, const char *key, satf_status status,
                           const char *fmt, ...) {
  size_t previous = scene_push_key(ctx, key);
  va_list ap;
  va_start(ap, fmt);
  satf_status s = fail_v(ctx, status, fmt, ap);
  va_end(ap);
  scene_pop(ctx, previous);
  return s;
}

satf_status scene_nomem(scene_ctx *ctx) {
  return satf_error_set(ctx->err, SATF_ERR_NOMEM, "%s: %s: out of memory",
                        ctx->name, current_path(ctx));
}

static satf_status append_warning(scene_ctx *ctx, const char *message) {
  satf_scene *scene = ctx->scene;
  size_t size =
      strlen(ctx->name) + strlen(current_path(ctx)) + strlen(message) + 5;
  char *text = malloc(size);
  char **grown = realloc(scene->warnings, (size_t)(scene->n_warnings + 1) *
                                              sizeof *scene->warnings);
  if (grown)
    scene->warnings = grown;
  if (!text || !grown) {
    free(text);
    return scene_nomem(ctx);
  }
  snprintf(text, size, "%s: %s: %s", ctx->name, current_path(ctx), message);
  scene->warnings[scene->n_warnings++] = text;
  return SATF_OK;
}

satf_status scene_warn(scene_ctx *ctx, const char *fmt, ...) {
  /* A file of nothing but unknown keys must not cost unbounded memory. */
  if (ctx->scene->n_warnings >= SCENE_WARNINGS_KEPT) {
    ctx->warnings_dropped++;
    return SATF_OK;
  }
  char message[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(message, sizeof message, fmt, ap);
  va_end(ap);
  return append_warning(ctx, message);
}

satf_status scene_warn_dropped(scene_ctx *ctx) {
  if (ctx->warnings_dropped == 0)
    return SATF_OK;
  char message[64];
  snprintf(message, sizeof message, "%d more warnings not shown",
           ctx->warnings_dropped);
  return append_warning(ctx, message);
}

const char *scene_quote(const char *text, char *buf, size_t size) {
  /* Keys and strings come from the file: keep messages one printable line
   * of bounded length whatever they contain. */
  size_t limit = size > 48 ? 48 : size;
  size_t o = 0;
  for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
    if (o + 5 >= limit) {
      memcpy(buf + o, "...", 4);
      return buf;
    }
    if (*p >= 0x20 && *p < 0x7f && *p != '\\') {
      buf[o++] = (char)*p;
    } else {
      o += (size_t)snprintf(buf + o, size - o, "\\x%02x", *p);
    }
  }
  buf[o] = '\0';
  return buf;
}
