/* scene_load.c - the entry points that make a scene: from JSON text
 * (satf_scene_parse), from a file (satf_scene_load), or with every default
 * for a program to fill in (satf_scene_create). */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_parse.h"

static void line_column(const char *text, size_t offset, int *line,
                        int *column) {
  *line = 1;
  *column = 1;
  for (size_t i = 0; i < offset; i++) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

static satf_status json_syntax_error(const char *name, const char *text,
                                     size_t len, size_t offset,
                                     const char *what, satf_error *err) {
  int line, column;
  if (offset > len)
    offset = len;
  line_column(text, offset, &line, &column);
  if (offset >= len)
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s:%d:%d: malformed JSON: unexpected end of input",
                          name, line, column);
  char near[24], quoted[64];
  size_t n = len - offset < sizeof near - 1 ? len - offset : sizeof near - 1;
  memcpy(near, text + offset, n);
  near[n] = '\0';
  for (size_t i = 0; i < n; i++)
    if (near[i] == '\n' || near[i] == '\r')
      near[i] = '\0';
  return satf_error_set(err, SATF_ERR_FORMAT, "%s:%d:%d: %s near \"%s\"", name,
                        line, column, what,
                        scene_quote(near, quoted, sizeof quoted));
}

static char *base_dir_of(const char *name) {
  const char *slash = strrchr(name, '/');
  if (!slash)
    return NULL;
  size_t n = (slash == name) ? 1 : (size_t)(slash - name);
  char *dir = malloc(n + 1);
  if (dir) {
    memcpy(dir, name, n);
    dir[n] = '\0';
  }
  return dir;
}

satf_status satf_scene_parse(const char *json, size_t len,
                             const char *name_for_messages, satf_scene **out,
                             satf_error *err) {
  const char *name = name_for_messages ? name_for_messages : "<scene>";
  if (!out)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: no output scene", name);
  *out = NULL;
  if (!json && len > 0)
    return satf_error_set(err, SATF_ERR_ARGUMENT, "%s: no JSON text", name);
  if (len > SATF_SCENE_MAX_FILE_BYTES)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "%s: %zu bytes is over the scene size limit of %u",
                          name, len, SATF_SCENE_MAX_FILE_BYTES);
  const char *nul = len ? memchr(json, '\0', len) : NULL;
  if (nul) {
    int line, column;
    line_column(json, (size_t)(nul - json), &line, &column);
    return satf_error_set(err, SATF_ERR_FORMAT,
                          "%s:%d:%d: NUL byte in the text", name, line, column);
  }

  /* cJSON decodes strings into C strings, so an escaped NUL would silently
   * cut a path short ("a\u0000b" read as "a"): refuse it. Escapes are
   * skipped pairwise so an escaped backslash followed by u0000 is text. */
  for (size_t i = 0; i + 1 < len; i++) {
    if (json[i] != '\\')
      continue;
    if (json[i + 1] == 'u' && i + 5 < len && json[i + 2] == '0' &&
        json[i + 3] == '0' && json[i + 4] == '0' && json[i + 5] == '0') {
      int line, column;
      line_column(json, i, &line, &column);
      return satf_error_set(err, SATF_ERR_FORMAT,
                            "%s:%d:%d: \\u0000 (a NUL character) in a string",
                            name, line, column);
    }
    i++;
  }

  /* cJSON reads a terminated copy, so it can never run past the caller's
   * buffer whatever the bytes are. */
  char *text = malloc(len + 1);
  if (!text)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  if (len)
    memcpy(text, json, len);
  text[len] = '\0';
  const char *end = NULL;
  cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
  if (!root) {
    size_t offset = end ? (size_t)(end - text) : 0;
    satf_status s =
        json_syntax_error(name, text, len, offset, "malformed JSON", err);
    free(text);
    return s;
  }

  satf_status s = SATF_OK;
  satf_scene *scene = calloc(1, sizeof *scene);
  char *base_dir = NULL;
  if (!scene || !(scene->name = malloc(strlen(name) + 1)) ||
      (strchr(name, '/') && !(base_dir = base_dir_of(name)))) {
    s = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  } else {
    strcpy(scene->name, name);
    scene_ctx ctx = {.name = name, .err = err, .scene = scene};
    s = scene_parse_root(&ctx, root, base_dir);
    if (s == SATF_OK)
      s = scene_warn_dropped(&ctx);
  }
  free(base_dir);
  cJSON_Delete(root);
  free(text);
  if (s != SATF_OK) {
    satf_scene_destroy(scene);
    return s;
  }
  *out = scene;
  return SATF_OK;
}

satf_status satf_scene_load(const char *path, satf_scene **out,
                            satf_error *err) {
  if (!out || !path)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_load: no path or no output scene");
  *out = NULL;
  FILE *f = fopen(path, "rb");
  if (!f)
    return satf_error_set(err, SATF_ERR_IO, "%s: cannot open: %s", path,
                          strerror(errno));
  /* Read in chunks rather than trusting a seek-reported size, so pipes and
   * files that change underneath work and the size cap holds. */
  size_t cap = 1 << 16, len = 0;
  char *buf = malloc(cap);
  satf_status s = SATF_OK;
  while (buf) {
    size_t got = fread(buf + len, 1, cap - len, f);
    len += got;
    if (got == 0)
      break;
    if (len == cap) {
      if (cap > SATF_SCENE_MAX_FILE_BYTES) {
        s = satf_error_set(err, SATF_ERR_ARGUMENT,
                           "%s: file is over the scene size limit of %u "
                           "bytes",
                           path, SATF_SCENE_MAX_FILE_BYTES);
        break;
      }
      char *grown = realloc(buf, cap * 2);
      if (!grown) {
        free(buf);
        buf = NULL;
        break;
      }
      buf = grown;
      cap *= 2;
    }
  }
  if (s == SATF_OK && !buf)
    s = satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", path);
  if (s == SATF_OK && ferror(f))
    s = satf_error_set(err, SATF_ERR_IO, "%s: read error: %s", path,
                       strerror(errno));
  fclose(f);
  if (s == SATF_OK)
    s = satf_scene_parse(buf, len, path, out, err);
  free(buf);
  return s;
}

satf_status satf_scene_create(const char *name, satf_scene **out,
                              satf_error *err) {
  if (!out || !name)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_create: no name or no output scene");
  *out = NULL;
  satf_scene *scene = calloc(1, sizeof *scene);
  if (!scene || !(scene->name = scene_copy_string(name))) {
    free(scene);
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory", name);
  }
  scene_ctx ctx = {.name = name, .err = err, .scene = scene};
  satf_status s = scene_parse_defaults(&ctx);
  if (s != SATF_OK) {
    satf_scene_destroy(scene);
    return s;
  }
  *out = scene;
  return SATF_OK;
}

satf_status satf_scene_add_mesh(satf_scene *scene, const char *file,
                                satf_error *err) {
  if (!scene || !file || scene->n_meshes >= SATF_SCENE_MAX_MESHES)
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "satf_scene_add_mesh: no scene, no file or over %d "
                          "meshes",
                          SATF_SCENE_MAX_MESHES);
  satf_scene_mesh *grown = realloc(
      scene->meshes, (size_t)(scene->n_meshes + 1) * sizeof *scene->meshes);
  if (!grown)
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                          scene->name);
  scene->meshes = grown;
  satf_scene_mesh *mesh = &scene->meshes[scene->n_meshes];
  memset(mesh, 0, sizeof *mesh);
  scene_parse_default_mesh(mesh);
  if (!(mesh->file = scene_copy_string(file)))
    return satf_error_set(err, SATF_ERR_NOMEM, "%s: out of memory",
                          scene->name);
  scene->n_meshes++;
  return SATF_OK;
}
