/* scene_fields.h - the scene format's simple fields described once: for
 * each object of the format (samples/README.md, Reference), its keys in
 * file order with, for a number, flag or 3-vector, the type, where the value
 * lives in the satf_scene struct, the default and the allowed range. The
 * parser (scene_fields_read), the writer (scene_write.c), the comparison
 * (scene_fields_equal) and the snapshot's clamps walk these tables, so a
 * key is named, typed, defaulted and bounded in one place. A key whose
 * value is more than that (a string, an enum, a default taken from another
 * key, keyframes) is a SCENE_FIELD_OTHER row: the tables still list it (the
 * allowed keys, the file order) and the object's own code reads and writes
 * it. */
#ifndef SATF_ONLINE_SCENE_FIELDS_H
#define SATF_ONLINE_SCENE_FIELDS_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "scene_values.h"

typedef enum scene_field_type {
  SCENE_FIELD_OTHER = 0, /* read and written by the object's own code */
  SCENE_FIELD_FLOAT,     /* a number, stored as float */
  SCENE_FIELD_INT,       /* an integer, stored as int */
  SCENE_FIELD_BOOL,      /* true or false, stored as int 0 or 1 */
  SCENE_FIELD_VEC3       /* 3 numbers, stored as float[3] */
} scene_field_type;

typedef struct scene_field {
  const char *key;
  scene_field_type type;
  size_t offset;     /* of the value in the struct the table describes */
  double def;        /* FLOAT, INT, BOOL */
  const float *def3; /* VEC3 */
  scene_range range; /* FLOAT, INT, VEC3 (each component) */
  int only_layout;   /* procedural density: 1 + the satf_scene_layout that
                        reads it (the others warn about it), 0: always */
  int above_default; /* written only when above the default: the default
                        (and below it) means unset */
} scene_field;

typedef struct scene_table {
  const char *name; /* samples/README.md's heading of the object's table */
  const scene_field *fields;
  int n;
} scene_table;

/* The objects: satf_scene_material, satf_scene_effects, satf_scene_image,
 * satf_scene_shell, satf_scene_density (procedural, tracks),
 * satf_scene_camera and satf_scene_light (whose rows the keyframes and
 * the snapshot share). */
extern const scene_table SCENE_MATERIAL, SCENE_EFFECTS, SCENE_IMAGE,
    SCENE_SHELL, SCENE_PROCEDURAL, SCENE_TRACKS, SCENE_CAMERA, SCENE_LIGHT;
/* All of them, for the tests: SCENE_TABLES[0..SCENE_N_TABLES). */
extern const scene_table *const SCENE_TABLES[];
extern const int SCENE_N_TABLES;

/* The row of key in t; NULL when t has none. */
const scene_field *scene_field_find(const scene_table *t, const char *key);

/* Reads an OTHER row's key (row->key) of obj into base; called in the
 * table's order between the simple rows. */
typedef satf_status (*scene_field_read_fn)(scene_ctx *ctx, const cJSON *obj,
                                           const scene_field *row, void *base,
                                           void *user);

/* Warns about each key of obj that t does not list (scene_check_keys),
 * then reads every row of t in order into base: the simple rows with
 * their default and range, the OTHER rows through other (skipped when
 * NULL). Rows of every layout are read (only_layout: the warning is
 * scene_fields_warn_unused's). */
satf_status scene_fields_read(scene_ctx *ctx, const cJSON *obj,
                              const scene_table *t, void *base,
                              scene_field_read_fn other, void *user);

/* Warns about each key of obj that only layouts other than layout read
 * ("ignored: only used by layout ..."). */
satf_status scene_fields_warn_unused(scene_ctx *ctx, const cJSON *obj,
                                     const scene_table *t, int layout,
                                     const char *const *layout_names);

/* Whether the simple rows of t hold the same bits in a and b. */
int scene_fields_equal(const scene_table *t, const void *a, const void *b);

/* Where row's value lives in base. */
static inline void *scene_field_at(const scene_field *row, void *base) {
  return (char *)base + row->offset;
}
static inline const void *scene_field_at_const(const scene_field *row,
                                               const void *base) {
  return (const char *)base + row->offset;
}

#endif
